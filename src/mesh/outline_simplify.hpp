// Fewer nodes on a body's outline before it is meshed anew: a node goes
// where its two neighbours are closer than the target element size and the
// triangle it spans with them is small, so the outline keeps its shape,
// its area and its volume to a stated tolerance. Without it the outline
// only gains nodes over a run (nodes crowd where the surface is
// compressed or rolls onto a die, a quad subdivision halves every edge),
// and the elements behind them shrink with them.
#pragma once
#include <cstddef>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

struct OutlineSimplification {
  // mm, per node: it goes only if the edge that replaces its two is at most
  // this long (the target element size there).
  std::vector<double> max_length;
  // The sum of |volume| the dropped nodes' triangles add or remove, at most
  // this share of the polygon's volume (2 pi int r dA, axisymmetric; the
  // area, plane strain).
  double volume_tolerance = 1e-8;
  Geometry geometry = Geometry::PlaneStrain;
};

// x: a closed counter-clockwise polygon; fixed: nodes that stay whatever
// their place (corners of named sides, monitored nodes). Returns the
// indices of the nodes kept, in order. Shortest replacement edges go first,
// so the spacing evens out toward max_length.
std::vector<std::size_t> simplify_outline(const std::vector<Vec2>& x, const std::vector<bool>& fixed,
                                          const OutlineSimplification& how);

}  // namespace rpfem
