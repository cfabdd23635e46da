// Order of accuracy of the kernel's velocity field by a manufactured solution.
//
// The exact field is the homogeneous compression v0 = (a x, -a y) (plane
// strain) or (a r/2, -a z) (axisymmetric) plus a smooth divergence-free
// perturbation from a stream function, on the unit square with the exact
// velocity on the whole boundary. For a rigid-perfectly-plastic material
// (sigma_bar = K) the deviatoric stress s = (2/3)(K/epsdot_bar) e is
// computed exactly; the body force f = -div s that makes v* the solution is
// integrated into nodal forces (int N_a f dV, 3x3 Gauss). The discrete
// velocity's L2 error is measured with 3x3 Gauss. Bilinear elements should
// converge at order 2.
#pragma once
#include <vector>

#include "core/types.hpp"

namespace rpfem {

struct MmsResult {
  int n = 0;             // elements per side
  double h = 0;          // element size
  double l2_error = 0;   // || v_h - v* ||_L2 / || v* ||_L2
  // The effective strain rate's error || epsdot(v_h) - epsdot(v*) ||_L2 /
  // || epsdot(v*) ||_L2 (3x3 Gauss), and its recovery-based estimate
  // (mesh/error_indicator.hpp) from the 2x2 points' rates.
  double strain_rate_error = 0;
  double strain_rate_estimate = 0;
  int newton_iterations = 0;
  bool converged = false;
};

MmsResult run_mms(Geometry g, int n);

// Observed order between successive meshes, log(e1/e2)/log(h1/h2).
std::vector<double> observed_orders(const std::vector<MmsResult>& r);

}  // namespace rpfem
