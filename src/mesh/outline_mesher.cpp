#include "mesh/outline_mesher.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace rpfem {

namespace {

// The body's boundary edges chained into one closed counter-clockwise loop
// (the body on the left of each edge).
std::vector<Edge> boundary_loop(const std::vector<Edge>& edges) {
  std::map<Index, std::size_t> from;  // start node -> edge
  for (std::size_t k = 0; k < edges.size(); ++k)
    if (!from.emplace(edges[k].a, k).second)
      throw std::runtime_error("remeshing: the outline touches itself at node " + std::to_string(edges[k].a));
  std::vector<Edge> loop;
  for (std::size_t k = 0; loop.size() < edges.size();) {
    loop.push_back(edges[k]);
    const auto next = from.find(edges[k].b);
    if (next == from.end()) throw std::runtime_error("remeshing: the outline is not closed");
    k = next->second;
    if (k == 0) break;
  }
  if (loop.size() != edges.size())
    throw std::runtime_error("remeshing: the outline is more than one loop (a body with a hole)");
  return loop;
}

// gmsh's global state for one meshing, finalized however it ends.
struct GmshSession {
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    // One thread: an error in gmsh's OpenMP regions would end the process
    // instead of reaching the caller.
    gmsh::option::setNumber("General.NumThreads", 1);
    gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1);  // Blossom
    gmsh::model::add("outline");
  }
  ~GmshSession() { gmsh::finalize(); }
};

double signed_area(const std::vector<Vec2>& x, const std::array<Index, 4>& q) {
  double a = 0;
  for (int i = 0; i < 4; ++i) a += cross(x[q[i]], x[q[(i + 1) % 4]]);
  return 0.5 * a;
}

OutlineMesh mesh_outline_with_gmsh(const Mesh& old, const std::vector<Vec2>& x, int body, double size) {
  const std::string& name = old.body_names.at(body);
  const std::vector<Edge> loop = boundary_loop(old.sides.at(name + ".boundary"));
  const int n = static_cast<int>(loop.size());

  GmshSession session;
  // Points 1..n at the loop's nodes, line k + 1 from point k + 1 to the next.
  std::vector<int> lines(n);
  for (int k = 0; k < n; ++k) gmsh::model::geo::addPoint(x[loop[k].a](0), x[loop[k].a](1), 0, size, k + 1);
  for (int k = 0; k < n; ++k) lines[k] = gmsh::model::geo::addLine(k + 1, (k + 1) % n + 1, k + 1);
  const int surface = gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(lines)});
  gmsh::model::geo::synchronize();
  gmsh::model::mesh::setRecombine(2, surface);
  // Each line in segments of about the target size, their total even (a
  // mesh of quadrilaterals has an even number of boundary edges; Blossom
  // leaves a triangle otherwise): the longest segments get one more.
  std::vector<int> segments(n);
  int total = 0, longest = 0;
  for (int k = 0; k < n; ++k) {
    const double L = (x[loop[k].b] - x[loop[k].a]).norm();
    segments[k] = std::max(1, static_cast<int>(std::lround(L / size)));
    total += segments[k];
    const double Ll = (x[loop[longest].b] - x[loop[longest].a]).norm();
    if (L / segments[k] > Ll / segments[longest]) longest = k;
  }
  if (total % 2) ++segments[longest];
  for (int k = 0; k < n; ++k) gmsh::model::mesh::setTransfiniteCurve(lines[k], segments[k] + 1);
  // Blossom matching at the target size on frontal-Delaunay's triangles,
  // else on Delaunay's or MeshAdapt's (Mesh.Algorithm 5, 1); should each
  // leave a triangle, the mesh at twice the size inside split into
  // quadrilaterals (every element into 3 or 4; the outline's segments too,
  // so a later remesh keeps twice as many outline nodes).
  const auto all_quads = [] {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 2);
    return types.size() == 1 && types[0] == 3;
  };
  bool done = false;
  for (const int algorithm : {6, 5, 1}) {
    gmsh::model::mesh::clear();
    gmsh::option::setNumber("Mesh.Algorithm", algorithm);
    gmsh::model::mesh::generate(2);
    if ((done = all_quads())) break;
  }
  if (!done) {
    gmsh::model::mesh::clear();
    gmsh::option::setNumber("Mesh.Algorithm", 6);
    gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
    for (int k = 0; k < n; ++k) gmsh::model::mesh::setSize({{0, k + 1}}, 2 * size);
    gmsh::model::mesh::generate(2);
  }

  OutlineMesh out;
  Mesh& m = out.mesh;
  std::vector<std::size_t> tags;
  std::vector<double> coords, params;
  gmsh::model::mesh::getNodes(tags, coords, params);
  std::map<std::size_t, Index> id;  // gmsh node tag -> node id
  for (std::size_t i = 0; i < tags.size(); ++i) {
    id[tags[i]] = static_cast<Index>(m.x.size());
    m.x.emplace_back(coords[3 * i], coords[3 * i + 1]);
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
      if (signed_area(m.x, q) < 0) std::swap(q[1], q[3]);
      m.quads.push_back(q);
    }
  }
  m.body_names = {name};
  m.element_body.assign(m.quads.size(), 0);
  m.node_body.assign(m.x.size(), 0);

  // Which element each counter-clockwise edge (a, b) belongs to.
  std::map<std::pair<Index, Index>, Index> owner;
  for (Index e = 0; e < m.num_elements(); ++e)
    for (int i = 0; i < 4; ++i) owner[{m.quads[e][i], m.quads[e][(i + 1) % 4]}] = e;
  // Each old boundary edge as its chain of new edges, along the line's
  // parameter from its start point.
  out.kept.assign(old.x.size(), -1);
  std::map<std::pair<Index, Index>, std::vector<Edge>> chain;  // old (a, b) -> new edges
  const auto point_node = [&](int point) {
    gmsh::model::mesh::getNodes(tags, coords, params, 0, point);
    return id.at(tags.at(0));
  };
  for (int k = 0; k < n; ++k) {
    // The line's inner nodes by their parameter, between its end points.
    std::vector<Index> nodes{point_node(k + 1)};
    gmsh::model::mesh::getNodes(tags, coords, params, 1, lines[k], false, true);
    std::vector<std::size_t> order(tags.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return params[i] < params[j]; });
    for (std::size_t i : order) nodes.push_back(id.at(tags[i]));
    nodes.push_back(point_node((k + 1) % n + 1));
    std::vector<Edge>& c = chain[{loop[k].a, loop[k].b}];
    for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
      const Index a = nodes[i], b = nodes[i + 1];
      const auto it = owner.find({a, b});
      if (it == owner.end()) throw std::runtime_error("remeshing: a boundary edge of gmsh's mesh has no element");
      c.push_back({a, b, it->second});
    }
    out.kept[loop[k].a] = nodes.front();
  }
  for (const auto& [side, edges] : old.sides) {
    if (side.compare(0, name.size() + 1, name + ".") != 0) continue;
    std::vector<Edge>& rebuilt = m.sides[side];
    for (const Edge& e : edges) {
      const auto& c = chain.at({e.a, e.b});
      rebuilt.insert(rebuilt.end(), c.begin(), c.end());
    }
  }
  return out;
}

}  // namespace

OutlineMesh mesh_outline(const Mesh& old, const std::vector<Vec2>& x, int body, double size) {
  try {
    return mesh_outline_with_gmsh(old, x, body, size);
  } catch (const std::string& e) {  // gmsh reports its errors by throwing their text
    throw std::runtime_error("remeshing: gmsh: " + e);
  }
}

}  // namespace rpfem
