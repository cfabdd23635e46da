#include "mesh/quality.hpp"

#include <algorithm>
#include <cmath>

namespace rpfem {

MeshQuality mesh_quality(const Mesh& mesh) { return mesh_quality(mesh, mesh.x); }

MeshQuality mesh_quality(const Mesh& mesh, const std::vector<Vec2>& x) {
  MeshQuality q;
  q.min_area = INFINITY;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& n = mesh.quads[e];
    double sj = INFINITY, lmin = INFINITY, lmax = 0, area = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec2 p = x[n[k]], e1 = x[n[(k + 1) % 4]] - p, e2 = x[n[(k + 3) % 4]] - p;
      const double l1 = e1.norm(), l2 = e2.norm();
      const double cross = e1(0) * e2(1) - e1(1) * e2(0);
      sj = std::min(sj, l1 > 0 && l2 > 0 ? cross / (l1 * l2) : -1.0);
      lmin = std::min(lmin, l1);
      lmax = std::max(lmax, l1);
      area += 0.5 * (p(0) * x[n[(k + 1) % 4]](1) - x[n[(k + 1) % 4]](0) * p(1));
    }
    if (sj < q.min_scaled_jacobian || q.worst_jacobian_element < 0) {
      q.min_scaled_jacobian = sj;
      q.worst_jacobian_element = e;
    }
    const double ar = lmin > 0 ? lmax / lmin : INFINITY;
    if (ar > q.max_aspect_ratio || q.worst_aspect_element < 0) {
      q.max_aspect_ratio = ar;
      q.worst_aspect_element = e;
    }
    q.min_area = std::min(q.min_area, area);
  }
  return q;
}

}  // namespace rpfem
