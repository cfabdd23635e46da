#include "mesh/quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace rpfem {

MeshQuality mesh_quality(const Mesh& mesh) { return mesh_quality(mesh, mesh.x); }

MeshQuality mesh_quality(const Mesh& mesh, const std::vector<Vec2>& x) {
  MeshQuality q;
  if (mesh.quads.empty()) return q;
  q.min_scaled_jacobian = std::numeric_limits<double>::infinity();
  q.max_aspect_ratio = 0;
  q.min_area = std::numeric_limits<double>::infinity();
  q.min_gauss_jacobian = std::numeric_limits<double>::infinity();
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto& n = mesh.quads[e];
    // Edge k runs from node k to node k + 1; corner k lies between edges
    // k - 1 and k, its Jacobian is cross(edge k, -edge k-1).
    std::array<Vec2, 4> d;
    std::array<double, 4> len;
    for (int k = 0; k < 4; ++k) {
      d[k] = x[n[(k + 1) % 4]] - x[n[k]];
      len[k] = d[k].norm();
    }
    double sj = std::numeric_limits<double>::infinity(), area = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec2& p = d[(k + 3) % 4];
      const double det = p(0) * d[k](1) - p(1) * d[k](0);
      const double l = len[k] * len[(k + 3) % 4];
      sj = std::min(sj, l > 0 ? det / l : -1.0);  // a collapsed edge counts as inverted
      const Vec2& xk = x[n[k]];
      area += 0.5 * (xk(0) * d[k](1) - xk(1) * d[k](0));  // shoelace
    }
    // Non-finite coordinates (a diverged update) must not pass as good.
    if (!std::isfinite(area)) sj = -std::numeric_limits<double>::infinity();
    const double lmin = *std::min_element(len.begin(), len.end());
    const double ar = lmin > 0 ? *std::max_element(len.begin(), len.end()) / lmin
                               : std::numeric_limits<double>::infinity();
    // det J of the bilinear map at the 2x2 Gauss points (+-1/sqrt 3), with
    // dx/dxi = ((1 - eta)(x1 - x0) + (1 + eta)(x2 - x3)) / 4 and
    // dx/deta = ((1 - xi)(x3 - x0) + (1 + xi)(x2 - x1)) / 4 (Kobayashi, Oh,
    // Altan 1989, eq. 7.29).
    constexpr double g = 0.57735026918962576451;
    const Vec2 a = x[n[1]] - x[n[0]], b = x[n[2]] - x[n[3]], c = x[n[3]] - x[n[0]], dd = x[n[2]] - x[n[1]];
    double gj = std::numeric_limits<double>::infinity();
    for (double xi : {-g, g})
      for (double eta : {-g, g}) {
        const Vec2 jx = 0.25 * ((1 - eta) * a + (1 + eta) * b), je = 0.25 * ((1 - xi) * c + (1 + xi) * dd);
        gj = std::min(gj, jx(0) * je(1) - jx(1) * je(0));
      }
    if (!std::isfinite(area)) gj = -std::numeric_limits<double>::infinity();
    if (gj < q.min_gauss_jacobian) q.min_gauss_jacobian = gj, q.worst_gauss_element = e;
    if (sj < q.min_scaled_jacobian) q.min_scaled_jacobian = sj, q.worst_jacobian_element = e;
    if (ar > q.max_aspect_ratio) q.max_aspect_ratio = ar, q.worst_aspect_element = e;
    q.min_area = std::min(q.min_area, area);
  }
  return q;
}

}  // namespace rpfem
