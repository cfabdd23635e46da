// Friction in the ipopt formulation: the arctan law's dissipation potential
// (contact/friction_law.hpp; paper eq. 11-12) added to the step's objective
// at every pair with a bound B > 0,
//   E_T = B psi(gamma_T),  gamma_T = u . t (contact/pair_kinematics.hpp)
// with B fixed within a solve, so the objective stays a potential with a
// symmetric Hessian and Ipopt solves a convex problem. The bound follows
// the multipliers by a fixed point over the solves of a step (the kernel's
// contact passes):
//   friction factor: B = m k w on the pairs pressing in the last solve
//   Coulomb:         B = min(mu N, k w), N the last solve's multiplier
// k = sigma_bar / sqrt 3 of the slave's elements along its surface, w the
// slave node's lumped area (k w: the sticking bound, as in `direct`).
#pragma once
#include <array>
#include <vector>

#include "contact/friction_law.hpp"
#include "contact/pair_kinematics.hpp"

namespace rpfem {

struct FrictionTerm {
  double energy = 0;
  std::array<double, 6> grad{};   // dE/dV, V = (v_s, v_a, v_b)
  std::array<double, 36> hess{};  // column-major, 2k x 2k
};

// The term of one pair at nodal velocities v (slave, master a, master b).
FrictionTerm friction_term(const PairKinematics& k, double bound, double a, const std::array<Vec2, 3>& v);

// The bound of the law for a pair pressing with N (N > 0) and sticking bound kw.
double friction_bound(const FrictionLaw& law, double N, double kw);

}  // namespace rpfem
