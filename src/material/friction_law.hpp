// Friction on die contact, smoothed by the Chen-Kobayashi arctan law (Chen
// and Kobayashi 1978; Kobayashi, Oh, Altan 1989, eq. 6.37; paper eq. 11-12):
//
//   f = -tau_max (2/pi) atan(|v_s| / a) t,   t = v_s / |v_s|
//
// with v_s the sliding velocity relative to the die and a a small speed.
//   friction factor: tau_max = m k,           k = sigma_bar / sqrt(3)
//   Coulomb:         tau_max = min(mu p, k),  p the normal pressure
// A die carries its law (geometry/die.hpp); the contact formulations
// evaluate it, the elements never do.
//
// The law may instead be treated exactly (`regularization = "exact"` in its
// table): no smoothing speed, the slip rate zero where the friction force
// is below tau_max (stick) and the force tau_max opposing the slip
// elsewhere (slip), the conditions as complementarity functions solved by
// the semi-smooth Newton enforcement (formulations/ssn/ncp.hpp), or the
// dissipation as a slack per row of Ipopt's program
// (formulations/ipopt/ipopt_step_solver.hpp).
#pragma once
#include <string>

namespace rpfem {

struct FrictionLaw {
  enum class Kind { None, Factor, Coulomb };
  Kind kind = Kind::None;
  double m = 0;            // friction factor, 0..1
  double mu = 0;           // Coulomb coefficient
  double a_relative = 1e-3;  // a = a_relative * (largest prescribed speed of the scene)
  // `regularization`: the arctan law above or the exact law; Default (the
  // key unset): the enforcement's own (exact under ssn, arctan elsewhere).
  enum class Treatment { Default, Arctan, Exact };
  Treatment treatment = Treatment::Default;
  // Whether the law is treated exactly by an enforcement whose default is
  // exact_by_default.
  bool exact(bool exact_by_default) const {
    return kind != Kind::None && (treatment == Treatment::Exact || (treatment == Treatment::Default && exact_by_default));
  }
  std::string describe() const;
  // The smoothing speed a (mm/s) for the scene's speed scale (mm/s).
  double smoothing_speed(double speed_scale) const { return a_relative * speed_scale; }
};

// The dissipation potential of the arctan law per unit tau_max and its
// derivatives in the signed sliding speed s (mm/s):
//   psi(s)   = (2/pi) [ s atan(s/a) - (a/2) ln(1 + (s/a)^2) ]   (mm/s)
//   psi'(s)  = (2/pi) atan(s/a)                                 (-)
//   psi''(s) = (2/pi) a / (a^2 + s^2)                           (s/mm)
// so that tau_max * psi'(s) is the friction stress of the law above.
struct ArctanPotential {
  double psi = 0, dpsi = 0, d2psi = 0;
};
ArctanPotential arctan_potential(double s, double a);

}  // namespace rpfem
