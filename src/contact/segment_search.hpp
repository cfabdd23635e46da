// Node-to-segment contact search between deformable bodies (paper sec. 3.1,
// Fig. 2-3), shared by the contact formulations (the kernel does not use it).
//
// A contact surface is a chain of boundary edges of one body, each oriented
// with the body on its left, so its outward normal is (d_y, -d_x) / L.
// The search for a slave node S runs in two stages:
//   global: a bucket grid over the master segments' bounding boxes, grown by
//           the capture distance; a node looks only at its own cell (cost
//           O(1) per node instead of all pairs);
//   local:  for each candidate segment A-B the signed area of the triangle
//           (A, B, S), 2 area = (B - A) x (S - A), gives the signed gap
//           g = -2 area / |B - A| (> 0 outside the master, < 0 penetrated),
//           and the projection parameter s = (S - A).(B - A) / |B - A|^2
//           tells whether S lies over the segment (-0.05 <= s <= 1.05: a
//           node landing on a vertex with round-off sees both segments).
// Among the segments S lies over, the one with the smallest |g| is taken;
// near-ties (|g| within 1e-3 of a segment length: S on or next to a shared
// vertex, where the master surface has a kink at the edge of a contact
// zone) go to the segment that faces the slave surface best (its normal
// most opposite to the slave's normal at S), then to the one S lies deeper
// over. A node over none of them (beyond a convex corner of the master, or
// over a sliver segment) is assigned to the nearest master vertex within
// the capture distance, with the vertex's mean normal.
// The master surface at S is then the least-squares line through S, A and B
// (paper Fig. 3): its direction gives the contact normal and tangent, and
// the local coordinates of the three points on it give S's position xi on
// the segment, which interpolates the master velocity (paper eq. 9, 12).
#pragma once
#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace rpfem {

struct ContactSurface {
  int body = -1;
  std::vector<Edge> edges;   // oriented, the body on the left
  std::vector<Index> nodes;  // sorted, unique
  // Builds the surface from named sides of one body ("<body>.<side>").
  static ContactSurface from_sides(const Mesh& mesh, const std::vector<std::string>& sides);
  // Position of a surface node in `nodes`.
  int local(Index node) const {
    return static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), node) - nodes.begin());
  }
};

// The outward unit normal of a surface edge along d = x_b - x_a (the body
// on its left).
Vec2 outward(const Vec2& d);

// Mean edge length of a surface at coordinates x (mm; 0 without edges).
double mean_edge_length(const std::vector<Vec2>& x, const ContactSurface& s);

struct SegmentHit {
  int edge = -1;        // index into the master surface's edges
  double xi = 0;        // position on the segment: master velocity (1 - xi) v_a + xi v_b
  double gap = 0;       // mm, signed: > 0 outside the master, < 0 penetrated
  Vec2 normal = Vec2::Zero();  // unit, the master's outward normal at S (least-squares line)
  Vec2 point = Vec2::Zero();   // closest point on the master surface
  bool at_vertex = false;      // assigned to a vertex (xi is 0 or 1)
};

// Global stage: a uniform bucket grid over the master segments.
class SegmentGrid {
 public:
  SegmentGrid() = default;
  // The reach a discretization's `capture` may ask for, relative to the
  // mean master edge length: below 1e-6 it is under any mesh's round-off
  // scale (and a mortar edge's search samples would number 1e6 and more),
  // above 1e6 the whole model many times over.
  static constexpr double kCaptureMin = 1e-6, kCaptureMax = 1e6;
  // margin (mm): how far from a segment a node is still a candidate.
  SegmentGrid(const std::vector<Vec2>& x, const ContactSurface& master, double margin);
  // Segments whose grown bounding box contains p (possibly a few more).
  void candidates(const Vec2& p, std::vector<int>& out) const;

 private:
  Vec2 lo_ = Vec2::Zero();
  double cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> cells_;
};

// Local stage: the master segment of slave point p, if one is within
// `capture` (mm) of it on either side.
// slave_normal: the slave surface's outward normal at p (zero if unknown).
std::optional<SegmentHit> find_segment(const std::vector<Vec2>& x, const ContactSurface& master,
                                       const SegmentGrid& grid, const Vec2& p, double capture,
                                       const Vec2& slave_normal = Vec2::Zero());
// find_segment for every node of `slave` (with its surface normal), indexed
// like slave.nodes.
std::vector<std::optional<SegmentHit>> find_segments(const std::vector<Vec2>& x, const ContactSurface& slave,
                                                     const ContactSurface& master, const SegmentGrid& grid,
                                                     double capture);
// Outward unit normal at each node of a surface (the normalized sum of its
// edges' normals), indexed like surface.nodes.
std::vector<Vec2> node_normals(const std::vector<Vec2>& x, const ContactSurface& s);

// The least-squares line through p, a, b (paper Fig. 3): unit normal n
// (oriented along the outward normal of the segment a-b) and the position
// xi of p between a (0) and b (1) from the points' coordinates along the
// line, clamped to [0, 1].
struct LeastSquaresLine {
  Vec2 normal = Vec2::Zero();
  double xi = 0;
};
LeastSquaresLine least_squares_line(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace rpfem
