// Rigid-(visco)plastic flow stress and its dissipation potential.
//
//   sigma_bar = K (eps0 + eps_bar)^n (epsdot / epsdot_ref)^m      (paper eq. 13,
//   with the strain offset eps0 and the optional rate term)
//
// Below the limiting strain rate epsdot_lim the material is linear-viscous,
// sigma_bar = sigma_lim * epsdot / epsdot_lim (Kobayashi, Oh, Altan, "Metal
// forming and the finite-element method", 1989, sec. 6.5): the rigid zones
// keep a finite, positive stiffness.
#pragma once
#include <string>

namespace rpfem {

struct FlowStressLaw {
  double K = 0;           // MPa
  double n = 0;           // strain hardening exponent
  double eps0 = 0.01;     // strain offset (sigma_bar(0) = K eps0^n > 0)
  double m = 0;           // strain-rate sensitivity (0: rate independent)
  double rate_ref = 1.0;  // 1/s, reference strain rate of the rate term

  double yield(double eps_bar) const;  // K (eps0 + eps_bar)^n, MPa
};

// Values of the potential phi(epsdot) (d phi / d epsdot = sigma_bar) at a
// material point, for the element functional int phi dV (paper eq. 2).
struct FlowPoint {
  double phi = 0;       // MPa/s, dissipation density
  double sigma = 0;     // MPa, effective stress
  double dsigma = 0;    // MPa s, d sigma_bar / d epsdot
  bool rigid = false;   // below the limiting strain rate
};

// eps_bar: accumulated effective strain; epsdot: effective strain rate (>= 0);
// epsdot_lim: limiting strain rate (> 0).
FlowPoint flow_point(const FlowStressLaw& law, double eps_bar, double epsdot, double epsdot_lim);
// The same at the point's yield stress sy = law.yield(eps_bar) (MPa), where
// the caller has it already (a step's strains are fixed): the same bits.
FlowPoint flow_point_at_yield(const FlowStressLaw& law, double sy, double epsdot, double epsdot_lim);

// A named entry of the material library (K in MPa, converted from the paper's
// kgf/mm^2 at this point of input).
struct LibraryMaterial {
  std::string name;
  std::string source;
  double K_kgf_mm2;
  double n;
};
const LibraryMaterial* find_library_material(const std::string& name);
std::string library_material_names();

}  // namespace rpfem
