// A body's current outline meshed anew with gmsh (Geuzaine and Remacle
// 2009, libgmsh 4.8), for remeshing a deformed body.
// The outline is the body's boundary as the old mesh has it: every old
// boundary node becomes a gmsh point and every old boundary edge a line, so
// the polygon, and the area and volume (2 pi r dA) it bounds, are the old
// ones exactly (the mesher is volume-neutral), every node a boundary
// condition or contact surface may name stays where it is, and each old
// side is rebuilt on the new mesh along the same edges. Edges longer than
// the target size get nodes on them, an even number in all. The inside is
// meshed by gmsh's frontal-Delaunay algorithm (Mesh.Algorithm 6), else
// Delaunay's (5) or MeshAdapt (1), recombined into quadrilaterals by
// Blossom matching (Mesh.RecombinationAlgorithm 1); where each leaves a
// triangle, the mesh at twice the size is split into quadrilaterals
// (Mesh.SubdivisionAlgorithm 1). Not
// frontal-Delaunay for quads (Mesh.Algorithm 8): Debian's gmsh 4.8.4
// crashes in it (its cross field's octree); not the full-quad Blossom
// (RecombinationAlgorithm 3): it halves each outline line's 1D mesh, which
// a line of one element cannot, and throws inside an OpenMP region.
#pragma once
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace rpfem {

struct OutlineMesh {
  Mesh mesh;  // the body alone (body id 0, its name), its sides as before
  // Per node of the old mesh: its node in the new mesh, -1 off the outline.
  std::vector<Index> kept;
};

// Meshes body `body` of `old` (at coordinates x) with target element size
// `size` (mm). Throws std::runtime_error if the outline is not one closed
// loop or gmsh leaves an element that is not a quadrilateral.
OutlineMesh mesh_outline(const Mesh& old, const std::vector<Vec2>& x, int body, double size);

}  // namespace rpfem
