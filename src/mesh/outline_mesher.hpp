// A body's current outline meshed anew with gmsh (Geuzaine and Remacle
// 2009, libgmsh 4.8), for remeshing a deformed body.
// The outline is the body's boundary as the old mesh has it, less the
// nodes that may go (OutlineOptions::volume_tolerance): every node kept
// stays where it is and the straight edge to the next one is split into
// segments of about the target size there (an even number in all), their
// points on the edge unless OutlineOptions::place moves them (out of a
// die's corner); each point is a gmsh point and each segment a line of one
// element. So the polygon, and the area and volume (2 pi r dA) it bounds,
// are the old ones to that tolerance (exactly where no node goes and no
// point is moved), the ends of every named side stay where they are, and
// each old side is rebuilt on the new mesh along the same edges. The
// inside is graded to OutlineOptions::size_at and meshed into
// quadrilaterals by gmsh (mesh/polygon_quad_mesher.hpp).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace rpfem {

struct OutlineMesh {
  Mesh mesh;  // the body alone (body id 0, its name), its sides as before
  // Per node of the old mesh: its node in the new mesh, -1 off the outline
  // or dropped from it.
  std::vector<Index> kept;
  // gmsh's fallback subdivided the mesh, every outline line split in two
  // (mesh/polygon_quad_mesher.hpp): a finer mesh than asked for.
  bool subdivided = false;
};

struct OutlineOptions {
  double size = 0;  // mm, the target element size
  // mm, the target size at a point, where it varies (empty: `size`
  // everywhere); gmsh grades the elements to it.
  std::function<double(const Vec2&)> size_at;
  // Old boundary nodes may go (mesh/outline_simplify.hpp) where the edge
  // replacing their two is at most `size` long and all the triangles so cut
  // off or added sum to at most this share of the body's volume; 0: only
  // nodes exactly in line with their neighbours. The ends of every named
  // side and the pinned nodes stay.
  double volume_tolerance = 0;
  Geometry geometry = Geometry::PlaneStrain;  // the volume that tolerance measures
  std::vector<Index> pinned;                  // old nodes that stay
  // Where a new outline point goes, at parameter s of the straight edge
  // from kept node a to kept node b (empty: a + s (b - a)); the caller
  // moves it out of a die the edge cuts into.
  std::function<Vec2(const Vec2& a, const Vec2& b, double s)> place;
};

// Meshes body `body` of `old` (at coordinates x). Throws std::runtime_error
// if the outline is not one closed loop, or where mesh_polygon_into_quads()
// does.
OutlineMesh mesh_outline(const Mesh& old, const std::vector<Vec2>& x, int body, const OutlineOptions& options);

}  // namespace rpfem
