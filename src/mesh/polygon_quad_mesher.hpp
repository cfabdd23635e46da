// A polygon meshed into quadrilaterals by gmsh (Geuzaine and Remacle 2009,
// libgmsh 4.8), the part of remeshing that calls gmsh. gmsh is loaded at
// the first call, from rpfem's module librpfem_gmsh.so
// (mesh/gmsh_module/), not linked into the programs: it brings about 120
// libraries (OpenCASCADE, FLTK, X11, ...) whose symbol binding took 0.11 to
// 0.22 s at every start of a program that may never remesh
// (docs/decisions.md, "Remeshing").
#pragma once
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

struct PolygonQuadMeshInput {
  // The polygon's points, counter-clockwise; line i runs from points[i] to
  // points[i + 1] (the last to the first) and is meshed as one edge.
  std::vector<Vec2> points;
  // mm, the target element size at a point; gmsh grades the elements to
  // it.
  std::function<double(const Vec2&)> size;
};

struct PolygonQuadMesh {
  std::vector<Vec2> x;                      // the nodes
  std::vector<std::array<Index, 4>> quads;  // counter-clockwise
  std::vector<Index> point_node;            // per polygon point: its node
  // Per line: the nodes strictly between its ends, in order from its
  // start (none, unless the fallback subdivision split the line).
  std::vector<std::vector<Index>> line_nodes;
};

// Meshes the polygon: gmsh's frontal-Delaunay algorithm (Mesh.Algorithm 6),
// else Delaunay's (5) or MeshAdapt (1), recombined into quadrilaterals by
// Blossom matching (Mesh.RecombinationAlgorithm 1); where each leaves a
// triangle, the same at sizes 3 and 6 % off the target; where those do
// too, the mesh at twice the size is split into quadrilaterals
// (Mesh.SubdivisionAlgorithm 1; every line gets a midpoint). Not
// frontal-Delaunay for quads (Mesh.Algorithm 8): Debian's gmsh 4.8.4
// crashes in it (its cross field's octree); not the full-quad Blossom
// (RecombinationAlgorithm 3): it halves each line's 1D mesh, which a line
// of one element cannot, and throws inside an OpenMP region. The polygon
// needs an even number of lines (a mesh of quadrilaterals has an even
// number of boundary edges). Throws std::runtime_error ("remeshing: ...")
// where gmsh fails, leaves an element that is not a quadrilateral, or its
// module cannot be loaded.
PolygonQuadMesh mesh_polygon_into_quads(const PolygonQuadMeshInput& in);

// The real path of the module this process loaded; empty before its first
// remesh (for the run's record).
std::string gmsh_module_path();

// The module's entry point (extern "C", looked up by name).
using MeshPolygonIntoQuads = void (*)(const PolygonQuadMeshInput&, PolygonQuadMesh&);
inline constexpr const char* kMeshPolygonSymbol = "rpfem_mesh_polygon_into_quads";

}  // namespace rpfem
