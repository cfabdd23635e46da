// The penalty formulation's term for one contact pair: a slave node against
// a master segment of another body (3 nodes) or against a rigid die (1 node).
//
// Relative velocity u, gamma_N and gamma_T: contact/pair_kinematics.hpp.
// Normal (paper eq. 7-8), with the gap correction of the step:
//   r = gamma_N + g0 / dt   (the gap at the end of the step over dt, g0 the
//                            gap where the velocity moves the nodes from;
//                            without the correction r = gamma_N, exactly eq. 7)
//   E_N = (beta / 2) r^2,   N = -beta r  (normal contact force, > 0 pressing)
//   one-sided (with the gap correction, the default): r is the predicted gap
//   at the end of the step over dt, and only its negative part is penalized,
//   E_N = (beta / 2) min(r, 0)^2: a node that would end the step inside its
//   master is pushed back onto it, a node that would separate carries no
//   force (C1, convex; the contact state is no longer a separate unknown).
// Friction (paper eq. 11, Chen-Kobayashi arctan law), potential B psi(gamma_T)
// (contact/friction_law.hpp) with the bound
//   factor:  B = m k w
//   Coulomb: B = min(mu max(N, 0), k w)    (paper eq. 11, capped at the
//            shear yield k of the softer body as in the direct formulation)
// Gradient and Hessian are exact; with Coulomb friction B depends on the
// velocities through N, which adds the unsymmetric block
//   psi'(gamma_T) (c (x) t) (dB/dV)^T,  dB/dV = -mu beta (c (x) n)
// (the consistent tangent), and the term is not a potential; with the bound
// frozen at an iterate (PairLaw::merit_bound) its energy is the merit whose
// gradient there is the term's gradient.
#pragma once
#include <array>

#include "contact/friction_law.hpp"
#include "contact/pair_kinematics.hpp"
#include "core/types.hpp"

namespace rpfem {

struct PairLaw {
  double beta = 0;            // N s/mm
  double inv_dt = 0;          // 1/dt with the gap correction, else 0
  bool one_sided = false;     // penalize only r < 0
  bool keep_stiffness = false;  // one-sided, r > 0: still return 1e-6 beta dn dn^T
                                // (a pair in contact lifted by an iterate: keeps
                                // a body held only by contacts from floating in
                                // the Newton matrix; not the exact Hessian, which
                                // slows Newton by about 1e-6 beta / (1e-6 beta + K)
                                // per iteration in that pair's direction: 1e-2
                                // of an element's stiffness at the default beta). At
                                // r = 0 exactly (a node resting at zero gap at
                                // the start) the full beta is used.
  FrictionLaw::Kind kind = FrictionLaw::Kind::None;
  double m = 0, mu = 0;
  double k_weight = 0;        // N: shear-yield bound k w
  double a = 1;               // smoothing speed, mm/s
  // >= 0: the bound in the energy only (the line search's merit anchored at
  // an iterate, ContactFormulation::anchor_merit); gradient and Hessian use
  // the live bound.
  double merit_bound = -1;
};

struct PairResult {
  double energy = 0;
  std::array<double, 6> grad{};      // dE/dV, V = (v_s, v_a, v_b) stacked
  std::array<double, 36> hess{};     // column-major, 2k x 2k used
  double normal_force = 0;           // N, > 0 pressing
  double bound = 0;                  // N, friction bound B
  double friction = 0;               // N, friction force on the slave along t
  double gamma_n = 0, gamma_t = 0;   // mm/s
};

// want_hess: fill the Hessian (else left zero).
PairResult pair_terms(const PairKinematics& p, const PairLaw& law, const std::array<Vec2, 3>& v, bool want_hess);

}  // namespace rpfem
