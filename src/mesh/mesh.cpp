#include "mesh/mesh.hpp"

#include <algorithm>

namespace rpfem {

std::vector<Index> Mesh::side_nodes(const std::string& side) const {
  auto it = sides.find(side);
  if (it == sides.end()) {
    std::string known;
    for (const auto& [name, e] : sides) known += (known.empty() ? "" : ", ") + name;
    throw InputError("unknown boundary side '" + side + "'; known: " + known);
  }
  std::vector<Index> n;
  for (const Edge& e : it->second) {
    n.push_back(e.a);
    n.push_back(e.b);
  }
  std::sort(n.begin(), n.end());
  n.erase(std::unique(n.begin(), n.end()), n.end());
  return n;
}

double Mesh::size() const {
  if (x.empty()) return 0.0;
  Vec2 lo = x.front(), hi = lo;
  for (const auto& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (hi - lo).maxCoeff();
}

void Mesh::append(const Mesh& o) {
  // Side names carry the body name: a second body of the same name would
  // silently merge its sides into the first one's.
  for (const auto& name : o.body_names)
    if (std::find(body_names.begin(), body_names.end(), name) != body_names.end())
      throw InputError("duplicate body name '" + name + "'");
  const Index dn = num_nodes(), de = num_elements();
  const int db = num_bodies();
  x.insert(x.end(), o.x.begin(), o.x.end());
  for (auto q : o.quads) {
    for (auto& n : q) n += dn;
    quads.push_back(q);
  }
  for (int b : o.element_body) element_body.push_back(b + db);
  for (int b : o.node_body) node_body.push_back(b + db);
  body_names.insert(body_names.end(), o.body_names.begin(), o.body_names.end());
  for (const auto& [name, edges] : o.sides) {
    auto& dst = sides[name];
    for (Edge e : edges) dst.push_back({e.a + dn, e.b + dn, e.element + de});
  }
}

}  // namespace rpfem
