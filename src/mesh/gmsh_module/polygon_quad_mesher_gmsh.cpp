// rpfem's gmsh module (librpfem_gmsh.so): mesh_polygon_into_quads()'s work,
// the only code that calls gmsh, loaded by mesh/polygon_quad_mesher.cpp at
// the first remesh.
#include <gmsh.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

#include "mesh/polygon_quad_mesher.hpp"

namespace rpfem {

namespace {

// gmsh's global state for one meshing, finalized however it ends.
struct GmshState {
  GmshState() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    // One thread: an error in gmsh's OpenMP regions would end the process
    // instead of reaching the caller.
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1);  // Blossom
    gmsh::model::add("outline");
  }
  ~GmshState() { gmsh::finalize(); }
};

// The target size's scales tried, in order, where Blossom leaves a
// triangle at the target itself.
constexpr double kNearScales[] = {0.97, 1.03, 0.94, 1.06};

double signed_area(const std::vector<Vec2>& x, const std::array<Index, 4>& q) {
  double a = 0;
  for (int i = 0; i < 4; ++i) a += cross(x[q[i]], x[q[(i + 1) % 4]]);
  return 0.5 * a;
}

void mesh_with_gmsh(const PolygonQuadMeshInput& in, PolygonQuadMesh& out) {
  const std::vector<Vec2>& points = in.points;
  const int np = static_cast<int>(points.size());
  // The target size at a point; `scale` doubles it for the subdivision below.
  double scale = 1;
  const auto h = [&](const Vec2& p) { return scale * in.size(p); };

  GmshState gmsh_state;
  // gmsh point i + 1 at points[i], line i + 1 from it to the next.
  std::vector<int> lines(np);
  for (int i = 0; i < np; ++i) gmsh::model::geo::addPoint(points[i](0), points[i](1), 0, h(points[i]), i + 1);
  for (int i = 0; i < np; ++i) lines[i] = gmsh::model::geo::addLine(i + 1, (i + 1) % np + 1, i + 1);
  const int surface = gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(lines)});
  gmsh::model::geo::synchronize();
  gmsh::model::mesh::setRecombine(2, surface);
  for (int i = 0; i < np; ++i) gmsh::model::mesh::setTransfiniteCurve(lines[i], 2);
  // The inside graded to the same target (gmsh takes the least of this and
  // the points' sizes).
  gmsh::model::mesh::setSizeCallback([&](int, int, double px, double py, double) { return h(Vec2(px, py)); });
  // Blossom matching at the target size on frontal-Delaunay's triangles,
  // else on Delaunay's or MeshAdapt's (Mesh.Algorithm 5, 1); should each
  // leave a triangle, the same at sizes a few per cent off the target
  // (kNearScales; the boundary stays as given, one edge a line): Blossom's
  // matching depends on the triangulation, and a slightly other one
  // matches. Only should these fail too, the mesh at twice the size inside
  // split into quadrilaterals (every element into 3 or 4; the lines too,
  // their midpoints in line). That halves the outline's spacing, which the
  // next remesh's simplification undoes only within its volume tolerance,
  // so each subdivision refined the next meshes: core_in_sleeve under
  // penalty with two pass remeshed into 676, 1,894 and 3,197 elements and
  // stopped at 4.92 mm; with the near sizes tried first, into 330 and 339,
  // and it finishes (docs/decisions.md, "Remeshing").
  const auto all_quads = [] {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 2);
    return types.size() == 1 && types[0] == 3;
  };
  const auto generate = [&](int algorithm, double at_scale) {
    if (at_scale != scale) {
      scale = at_scale;
      for (int i = 0; i < np; ++i) gmsh::model::mesh::setSize({{0, i + 1}}, h(points[i]));
    }
    gmsh::model::mesh::clear();
    gmsh::option::setNumber("Mesh.Algorithm", algorithm);
    gmsh::model::mesh::generate(2);
    return all_quads();
  };
  bool done = false;
  for (const int algorithm : {6, 5, 1})
    if ((done = generate(algorithm, 1.0))) break;
  for (const double near : kNearScales) {
    if (done) break;
    for (const int algorithm : {6, 5})
      if ((done = generate(algorithm, near))) break;
  }
  if (!done) {
    gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
    generate(6, 2.0);
  }
  gmsh::model::mesh::removeSizeCallback();

  std::vector<std::size_t> tags;
  std::vector<double> coords, params;
  gmsh::model::mesh::getNodes(tags, coords, params);
  std::map<std::size_t, Index> id;  // gmsh node tag -> node id
  for (std::size_t i = 0; i < tags.size(); ++i) {
    id[tags[i]] = static_cast<Index>(out.x.size());
    out.x.emplace_back(coords[3 * i], coords[3 * i + 1]);
  }
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags, element_nodes;
  gmsh::model::mesh::getElements(types, element_tags, element_nodes, 2);
  for (std::size_t t = 0; t < types.size(); ++t) {
    if (types[t] != 3)  // 3: the 4-node quadrilateral
      throw std::runtime_error("remeshing: gmsh left " + std::to_string(element_tags[t].size()) +
                               " elements that are not quadrilaterals");
    for (std::size_t e = 0; e < element_tags[t].size(); ++e) {
      std::array<Index, 4> q;
      for (int i = 0; i < 4; ++i) q[i] = id.at(element_nodes[t][4 * e + i]);
      if (signed_area(out.x, q) < 0) std::swap(q[1], q[3]);
      out.quads.push_back(q);
    }
  }
  // Each point's node, and each line's nodes between its ends by their
  // parameter on the line.
  out.point_node.resize(np);
  out.line_nodes.assign(np, {});
  for (int i = 0; i < np; ++i) {
    gmsh::model::mesh::getNodes(tags, coords, params, 0, i + 1);
    out.point_node[i] = id.at(tags.at(0));
    gmsh::model::mesh::getNodes(tags, coords, params, 1, lines[i], false, true);
    std::vector<std::size_t> order(tags.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return params[a] < params[b]; });
    for (std::size_t j : order) out.line_nodes[i].push_back(id.at(tags[j]));
  }
}

}  // namespace

}  // namespace rpfem

extern "C" __attribute__((visibility("default"))) void rpfem_mesh_polygon_into_quads(
    const rpfem::PolygonQuadMeshInput& in, rpfem::PolygonQuadMesh& out) {
  try {
    rpfem::mesh_with_gmsh(in, out);
  } catch (const std::string& e) {  // gmsh reports its errors by throwing their text
    throw std::runtime_error("remeshing: gmsh: " + e);
  }
}
