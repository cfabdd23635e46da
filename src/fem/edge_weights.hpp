// Lumped weights of a straight boundary edge a-b: w_a = int N_a dS, with
// dS = ds in plane strain (per mm of depth) and dS = 2 pi r ds in axisymmetry
// (the whole ring): L/2 each, or 2 pi L (2 r_a + r_b)/6 and 2 pi L (r_a + 2 r_b)/6.
#pragma once
#include <array>

#include "core/types.hpp"

namespace rpfem {

inline std::array<double, 2> edge_weights(const Vec2& xa, const Vec2& xb, Geometry g) {
  const double L = (xb - xa).norm();
  if (g == Geometry::Axisymmetric)
    return {2 * kPi * L * (2 * xa(0) + xb(0)) / 6.0, 2 * kPi * L * (xa(0) + 2 * xb(0)) / 6.0};
  return {0.5 * L, 0.5 * L};
}

}  // namespace rpfem
