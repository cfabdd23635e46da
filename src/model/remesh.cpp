#include "model/remesh.hpp"

#include <algorithm>
#include <stdexcept>

#include "fem/quad4.hpp"
#include "mesh/field_transfer.hpp"
#include "mesh/outline_mesher.hpp"

namespace rpfem {

namespace {

// One body of a mesh on its own, at coordinates x, with the state's
// fields on it: its nodes and elements renumbered in order.
struct BodyPart {
  Mesh mesh;
  std::vector<GaussValues> strain;
  std::vector<Vec2> v;
  std::vector<Index> node;  // per node of the whole mesh: its node in the part (-1: another body's)
};

BodyPart body_part(const Mesh& m, const RunState& st, int body) {
  BodyPart p;
  std::vector<Index>& node = p.node;
  node.assign(m.num_nodes(), -1);
  std::vector<Index> element(m.num_elements(), -1);
  for (Index n = 0; n < m.num_nodes(); ++n)
    if (m.node_body[n] == body) {
      node[n] = static_cast<Index>(p.mesh.x.size());
      p.mesh.x.push_back(st.x[n]);
      p.v.push_back(st.v.size() == st.x.size() ? st.v[n] : Vec2::Zero());
    }
  for (Index e = 0; e < m.num_elements(); ++e)
    if (m.element_body[e] == body) {
      element[e] = p.mesh.num_elements();
      auto q = m.quads[e];
      for (Index& n : q) n = node[n];
      p.mesh.quads.push_back(q);
      p.strain.push_back(st.strain[e]);
    }
  const std::string& name = m.body_names[body];
  p.mesh.body_names = {name};
  p.mesh.element_body.assign(p.mesh.quads.size(), 0);
  p.mesh.node_body.assign(p.mesh.x.size(), 0);
  for (const auto& [side, edges] : m.sides) {
    if (side.compare(0, name.size() + 1, name + ".") != 0) continue;
    auto& out = p.mesh.sides[side];
    for (const Edge& e : edges) out.push_back({node[e.a], node[e.b], element[e.element]});
  }
  return p;
}

// Volume, int eps dV and the largest eps over the mesh's 2x2 points.
struct Totals {
  double volume = 0, integral = 0, max = 0;
};

Totals totals(const Mesh& m, const std::vector<Vec2>& x, const std::vector<GaussValues>& strain, Geometry g) {
  Totals t;
  for (Index e = 0; e < m.num_elements(); ++e) {
    const Quad4Coords X{x[m.quads[e][0]], x[m.quads[e][1]], x[m.quads[e][2]], x[m.quads[e][3]]};
    for (int q = 0; q < 4; ++q) {
      const double w = volume_weight(quad4_point(X, kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]), g, 1.0);
      t.volume += w, t.integral += w * strain[e][q], t.max = std::max(t.max, strain[e][q]);
    }
  }
  return t;
}

double relative(double after, double before) { return before != 0 ? after / before - 1 : after - before; }

}  // namespace

RemeshChange remesh_change(const Scene& before, const RunState& old_state, const RemeshedScene& after) {
  const Totals a = totals(before.mesh, old_state.x, old_state.strain, before.geometry);
  const Totals b = totals(after.scene.mesh, after.state.x, after.state.strain, before.geometry);
  return {relative(b.volume, a.volume), relative(b.integral, a.integral), relative(b.max, a.max)};
}

RemeshedScene remesh_scene(const Scene& scene, const RunState& state, const std::vector<int>& bodies,
                           const std::vector<double>& size) {
  if (bodies.size() != size.size()) throw std::invalid_argument("remesh_scene: one size per body");
  RemeshedScene out{scene, {}, std::vector<Index>(scene.mesh.num_nodes(), -1)};
  Mesh mesh;
  RunState& st = out.state;
  st.time = state.time, st.stroke = state.stroke, st.step = state.step;
  for (int b = 0; b < scene.mesh.num_bodies(); ++b) {
    BodyPart part = body_part(scene.mesh, state, b);
    const auto listed = std::find(bodies.begin(), bodies.end(), b);
    if (listed != bodies.end()) {
      OutlineMesh fresh = mesh_outline(part.mesh, part.mesh.x, 0, size[listed - bodies.begin()]);
      part.strain = transfer_gauss_field(part.mesh, part.mesh.x, part.strain, fresh.mesh, fresh.mesh.x);
      part.v = transfer_nodal_field(part.mesh, part.mesh.x, part.v, fresh.mesh.x);
      part.mesh = std::move(fresh.mesh);
      for (Index& n : part.node)
        if (n >= 0) n = fresh.kept[n];
    }
    const Index offset = mesh.num_nodes();
    for (Index n = 0; n < scene.mesh.num_nodes(); ++n)
      if (part.node[n] >= 0) out.kept[n] = offset + part.node[n];
    mesh.append(part.mesh);
    st.x.insert(st.x.end(), part.mesh.x.begin(), part.mesh.x.end());
    st.v.insert(st.v.end(), part.v.begin(), part.v.end());
    st.strain.insert(st.strain.end(), part.strain.begin(), part.strain.end());
  }
  out.scene.mesh = std::move(mesh);
  return out;
}

}  // namespace rpfem
