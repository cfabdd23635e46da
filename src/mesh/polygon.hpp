// Measures of a body's outline polygon: the volume an edge sweeps (Green's
// theorem, with its gradient) and a point's distance to an edge. Shared by
// the outline's simplification, the remesh's volume restoration and the
// die-interference trigger.
#pragma once
#include <algorithm>

#include "core/types.hpp"

namespace rpfem {

// The volume an edge a -> b sweeps with the origin: the area (plane strain)
// or 2 pi int r dA (axisymmetric, Pappus), exact for a straight edge; the
// sum over a closed counter-clockwise polygon is its volume. da, db: its
// gradients with respect to a and b.
struct EdgeVolume {
  double v;
  Vec2 da, db;
};
inline EdgeVolume edge_volume(const Vec2& a, const Vec2& b, Geometry g) {
  const double c = 0.5 * cross(a, b);
  const Vec2 dc_da(0.5 * b(1), -0.5 * b(0)), dc_db(-0.5 * a(1), 0.5 * a(0));
  if (g != Geometry::Axisymmetric) return {c, dc_da, dc_db};
  const double k = 2 * kPi / 3, r = a(0) + b(0);
  return {k * c * r, k * (dc_da * r + Vec2(c, 0)), k * (dc_db * r + Vec2(c, 0))};
}

// Distance from p to the segment a b.
inline double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double L2 = d.squaredNorm();
  const double s = L2 > 0 ? std::clamp((p - a).dot(d) / L2, 0.0, 1.0) : 0.0;
  return (p - (a + s * d)).norm();
}

}  // namespace rpfem
