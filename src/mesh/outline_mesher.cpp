#include "mesh/outline_mesher.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>

#include "mesh/outline_simplify.hpp"
#include "mesh/polygon_quad_mesher.hpp"

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

// The sides of body `name` each edge (a, b) of the old mesh is on.
std::map<std::pair<Index, Index>, std::set<std::string>> sides_of_edges(const Mesh& old, const std::string& name) {
  std::map<std::pair<Index, Index>, std::set<std::string>> on;
  for (const auto& [side, edges] : old.sides)
    if (side.compare(0, name.size() + 1, name + ".") == 0)
      for (const Edge& e : edges) on[{e.a, e.b}].insert(side);
  return on;
}

}  // namespace

OutlineMesh mesh_outline(const Mesh& old, const std::vector<Vec2>& x, int body, const OutlineOptions& o) {
  // The target size at a point.
  const auto h = [&](const Vec2& p) { return o.size_at ? o.size_at(p) : o.size; };
  const std::string& name = old.body_names.at(body);
  const std::vector<Edge> all = boundary_loop(old.sides.at(name + ".boundary"));
  // The outline's corners: a node stays where the sides its two edges are
  // on differ (a side's end), or where it is pinned.
  const auto on = sides_of_edges(old, name);
  const std::set<Index> pinned(o.pinned.begin(), o.pinned.end());
  std::vector<Vec2> polygon;
  std::vector<bool> fixed;
  OutlineSimplification how{{}, o.volume_tolerance, o.geometry};
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Edge& before = all[(k + all.size() - 1) % all.size()];
    polygon.push_back(x[all[k].a]);
    fixed.push_back(pinned.count(all[k].a) || on.at({before.a, before.b}) != on.at({all[k].a, all[k].b}));
    how.max_length.push_back(h(polygon.back()));
  }
  const std::vector<std::size_t> corner = simplify_outline(polygon, fixed, how);
  // Line k from old node corner[k] to the next corner: loop[k] is that
  // straight edge; line_of names the line that replaces each old edge.
  const int n = static_cast<int>(corner.size());
  std::vector<Edge> loop(n);
  std::map<std::pair<Index, Index>, int> line_of;  // old boundary edge -> its line
  for (int k = 0; k < n; ++k) {
    const std::size_t end = corner[(k + 1) % n];
    loop[k] = {all[corner[k]].a, all[end].a, -1};
    for (std::size_t i = corner[k]; i != end; i = (i + 1) % all.size()) line_of[{all[i].a, all[i].b}] = k;
  }

  // Each line in segments of about the target size (int ds / h by
  // Simpson's rule), their total even (a mesh of quadrilaterals has an even
  // number of boundary edges; Blossom leaves a triangle otherwise): the
  // longest segments get one more.
  std::vector<int> segments(n);
  int total = 0, longest = 0;
  for (int k = 0; k < n; ++k) {
    const Vec2 &a = x[loop[k].a], &b = x[loop[k].b];
    const double count = (b - a).norm() / 6 * (1 / h(a) + 4 / h(0.5 * (a + b)) + 1 / h(b));
    segments[k] = std::max(1, static_cast<int>(std::lround(count)));
    total += segments[k];
    const double Ll = (x[loop[longest].b] - x[loop[longest].a]).norm();
    if ((b - a).norm() / segments[k] > Ll / segments[longest]) longest = k;
  }
  if (total % 2) ++segments[longest];
  // The outline's points: each line's start (its old node, where it was)
  // and its segments' ends between, evenly spaced on the straight line,
  // moved out of a die where OutlineOptions::place says. first[k]: the
  // point line k starts at.
  std::vector<Vec2> points;
  std::vector<int> first(n + 1);
  for (int k = 0; k < n; ++k) {
    first[k] = static_cast<int>(points.size());
    const Vec2 &a = x[loop[k].a], &b = x[loop[k].b];
    points.push_back(a);
    for (int i = 1; i < segments[k]; ++i) {
      const double t = static_cast<double>(i) / segments[k];
      points.push_back(o.place ? o.place(a, b, t) : Vec2(a + (b - a) * t));
    }
  }
  first[n] = static_cast<int>(points.size());
  const int np = first[n];

  PolygonQuadMeshInput polygon_in;
  polygon_in.points = points;
  polygon_in.size = h;
  PolygonQuadMesh polygon_mesh = mesh_polygon_into_quads(polygon_in);

  OutlineMesh out;
  out.subdivided = std::any_of(polygon_mesh.line_nodes.begin(), polygon_mesh.line_nodes.end(),
                               [](const std::vector<Index>& between) { return !between.empty(); });
  Mesh& m = out.mesh;
  m.x = std::move(polygon_mesh.x);
  m.quads = std::move(polygon_mesh.quads);
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
  std::vector<std::vector<Edge>> chain(n);  // per line: its new edges
  for (int k = 0; k < n; ++k) {
    // The nodes along line k: its points and, after a subdivision, the
    // nodes gmsh put between them.
    std::vector<Index> nodes;
    for (int i = first[k]; i < first[k + 1]; ++i) {
      nodes.push_back(polygon_mesh.point_node[i]);
      const auto& between = polygon_mesh.line_nodes[i];
      nodes.insert(nodes.end(), between.begin(), between.end());
    }
    nodes.push_back(polygon_mesh.point_node[first[k + 1] % np]);
    std::vector<Edge>& c = chain[k];
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
    // A side is whole lines (its ends are corners): each line's chain once,
    // in the side's order.
    std::vector<Edge>& rebuilt = m.sides[side];
    int last = -1;
    for (const Edge& e : edges) {
      const int k = line_of.at({e.a, e.b});
      if (k == last) continue;
      rebuilt.insert(rebuilt.end(), chain[k].begin(), chain[k].end());
      last = k;
    }
  }
  return out;
}

}  // namespace rpfem
