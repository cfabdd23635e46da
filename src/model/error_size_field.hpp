// The remesher's element size from the strain-rate error of the old mesh
// (remesh.target_error; docs/theory.md, "Sizes from the error"). Per old
// element e of a body, with eta_e its recovery-based error
// (mesh/error_indicator.hpp), h_e = sqrt(A_e) its size, ||epsdot_h|| the
// body's strain-rate norm and eta_bar the target relative error: the error
// spread equally over the N elements of the new mesh,
//
//   e_bar = eta_bar ||epsdot_h|| / sqrt(N),
//
// and, the element's error taken to scale as h^(p + 1) in two dimensions
// (the rate's error density as h^p, p = 1 for bilinear velocities, over an
// area h^2),
//
//   h_new,e = h_e (e_bar / eta_e)^(1 / (p + 1)),
//   N = sum_e (h_e / h_new,e)^2  =>  N = [sum_e (eta_e / (eta_bar ||epsdot_h||))^(2 / (p + 1))]^((p + 1) / p)
//
// (Li and Bettess, Commun. Numer. Methods Eng. 11 (1995) 911-915, their
// correction of the rule h_new = h_e (e_bar / eta_e)^(1 / p) with N the
// old count of Zienkiewicz and Zhu, IJNME 24 (1987) 337-357; the same
// estimator and rule for forming: Fourment and Chenot, Eng. Comput. 12
// (1995) 469-490). The size is then bounded to [min_size, max_size].
#pragma once
#include <functional>
#include <vector>

#include "core/types.hpp"
#include "mesh/field_transfer.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

struct ErrorSizeRule {
  double target = 0;    // eta_bar, the target relative error (> 0)
  double min_size = 0;  // mm, the bounds of the new size
  double max_size = 0;  // mm
};

struct ErrorSizes {
  std::vector<double> element;  // mm, the new size per old element (bounded)
  double predicted = 0;         // N, the new mesh's element count the rule predicts (unbounded)
  double relative = 0;          // the old mesh's relative error estimate
  // The size at any point: the elements' sizes averaged at the old nodes,
  // interpolated in the old element that holds the point. Empty where the
  // rate is zero everywhere (nothing to grade by).
  std::function<double(const Vec2&)> at;
};

// rate: the effective strain rate at the 2x2 points of each element of the
// body mesh m at coordinates x.
ErrorSizes error_sizes(const Mesh& m, const std::vector<Vec2>& x, const std::vector<GaussValues>& rate, Geometry g,
                       const ErrorSizeRule& rule);

}  // namespace rpfem
