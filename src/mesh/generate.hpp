// Structured quadrilateral meshes of the shapes the cases need, all built
// by one block mesher: blocks mapped from the unit square by transfinite
// (Coons) interpolation of their four boundary curves, coincident nodes of
// neighbouring blocks merged. Quads are counter-clockwise; boundary edges
// (used by one element) are oriented with the body on their left, named
// "<body>.<side>" after the block face they lie on and all of them also in
// "<body>.boundary"; each side is one counter-clockwise run of edges.
// Invalid dimensions or divisions < 1 throw InputError.
#pragma once
#include <array>
#include <string>

#include "mesh/mesh.hpp"

namespace rpfem {

struct RectangleSpec {
  double x0 = 0, y0 = 0, width = 1, height = 1;
  int nx = 10, ny = 10;
};
// Sides: bottom, right, top, left.
Mesh make_rectangle(const std::string& body, const RectangleSpec& s);

// A straight-sided quadrilateral block (a trapezoid, a conical punch's r-z
// section): corners counter-clockwise from the bottom-left one; nx divisions
// along bottom and top, ny along right and left.
struct QuadrilateralSpec {
  std::array<Vec2, 4> corners{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  int nx = 10, ny = 10;
};
// Sides: bottom, right, top, left. Throws InputError unless convex and
// counter-clockwise.
Mesh make_quadrilateral(const std::string& body, const QuadrilateralSpec& s);

struct RingSpec {
  double inner_radius = 1, outer_radius = 2, y0 = 0, height = 1;
  int nr = 10, ny = 10;
};
// The r-z section of a ring. Sides: bottom, outer, top, inner.
Mesh make_ring(const std::string& body, const RingSpec& s);

enum class DiskPart { Half, UpperQuarter, LowerQuarter };
struct DiskSpec {
  double radius = 1;
  double center_y = 0;
  DiskPart part = DiskPart::Half;
  int n = 8;       // divisions of the inner square's side
  int layers = 8;  // divisions between the square and the arc
};
// The x >= 0 part of a disk centred at (0, center_y): the r-z section of a
// sphere (half) or of its upper/lower half (quarter). An O-grid: per quarter
// an inner n x n quadrilateral and two layers x n blocks out to the arc
// (0..45, 45..90 degrees), so no element degenerates at the axis or the
// centre (min scaled Jacobian 0.865 for any n, layers). The half is the
// upper quarter and its mirror image. Arc nodes lie exactly on the circle,
// axis nodes at x = 0. Sides: arc, axis, and for quarters plane
// (y = center_y).
Mesh make_disk(const std::string& body, const DiskSpec& s);

}  // namespace rpfem
