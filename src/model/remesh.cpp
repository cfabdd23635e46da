#include "model/remesh.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <stdexcept>

#include "fem/quad4.hpp"
#include "mesh/field_transfer.hpp"
#include "mesh/outline_mesher.hpp"
#include "mesh/polygon.hpp"
#include "model/error_size_field.hpp"

namespace rpfem {

namespace {

// One body of a mesh on its own, at coordinates x, with the state's
// fields on it: its nodes and elements renumbered in order.
struct BodyPart {
  Mesh mesh;
  std::vector<GaussValues> strain, rate;  // rate: empty where the state has none
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
      if (st.rate.size() == st.strain.size()) p.rate.push_back(st.rate[e]);
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

// The target size at a point of body part p: `size`, falling to
// size * share at the dies' corners near the body (request.die_corner_size),
// linearly in the distance to the nearest over 4 sizes; at most size * far
// (1: `size` beyond 4 sizes).
std::function<double(const Vec2&)> corner_field(const Scene& scene, const BodyPart& p, double t, double size,
                                                double share, double far) {
  if (share >= 1) return {};
  std::vector<Vec2> near;
  const auto& outline = p.mesh.sides.at(p.mesh.body_names[0] + ".boundary");
  for (const Die& die : scene.dies)
    for (const Vec2& c : die.profile.corner_points(die.motion.displacement(t), false)) {
      double d = std::numeric_limits<double>::infinity();
      for (const Edge& e : outline) d = std::min(d, segment_distance(c, p.mesh.x[e.a], p.mesh.x[e.b]));
      if (d <= size) near.push_back(c);
    }
  if (near.empty()) return {};
  return [near, size, share, far](const Vec2& x) {
    double d = std::numeric_limits<double>::infinity();
    for (const Vec2& c : near) d = std::min(d, (x - c).norm());
    return size * std::min(far, share + (1 - share) * d / (4 * size));
  };
}

// The size field of body part p: the dies' corners' grading, and with
// request.target_error the size from the old mesh's error
// (model/error_size_field.hpp), the smaller of the two. Without a rate on
// the part (a state not solved) the grading alone, as without a target.
std::function<double(const Vec2&)> size_field(const Scene& scene, const BodyPart& p, double t, double size,
                                              const RemeshRequest& request) {
  ErrorSizes sizes;  // its `at` empty also where the rate is zero everywhere
  if (request.target_error > 0 && p.rate.size() == p.strain.size())
    sizes = error_sizes(p.mesh, p.mesh.x, p.rate, scene.geometry,
                        {request.target_error, request.min_size * size, request.max_size * size});
  if (!sizes.at) return corner_field(scene, p, t, size, request.die_corner_size, 1.0);
  const auto corner = corner_field(scene, p, t, size, request.die_corner_size, request.max_size);
  if (!corner) return sizes.at;
  return [corner, at = sizes.at](const Vec2& x) { return std::min(corner(x), at(x)); };
}

// Where a new outline point of body b goes, at parameter s of the edge
// from kept node a to kept node b: on the edge, unless that is deeper in a
// die its contact pairs name than the two nodes are (linearly between their
// depths: a penalty's penetration stays as it is), by less than the
// element size (deeper is the far side of a thin die, not an overlap);
// then at that depth below the die's surface. So an edge that cuts across
// a die's corner gets its new nodes on the corner.
std::function<Vec2(const Vec2&, const Vec2&, double)> die_placement(const Scene& scene, int b, double t,
                                                                    double size) {
  std::vector<const Die*> dies;
  for (const ContactPair& pair : scene.contact_pairs)
    if (pair.with_die() && pair.body_id == b) dies.push_back(&scene.dies[pair.die_id]);
  if (dies.empty()) return {};
  return [dies, t, size](const Vec2& a, const Vec2& bb, double s) {
    Vec2 p = a + s * (bb - a);
    for (const Die* die : dies) {
      const DieProjection at = die->project(p, t);
      const double allowed = (1 - s) * std::min(0.0, die->project(a, t).distance) +
                             s * std::min(0.0, die->project(bb, t).distance);
      if (at.distance < allowed && at.distance > -size) p = at.point + allowed * at.normal;
    }
    return p;
  };
}

// Moves body mesh m's free boundary nodes along their outward normals,
// all by the same distance, until the body's volume is `target` (Newton on
// that distance, a few iterations: the volume is quadratic in it). Free:
// off every die a contact pair of body b names (farther than `touch`), off
// the axis (axisymmetric) and the symmetry planes. Returns false where no
// node is free.
bool restore_volume(Mesh& m, const Scene& scene, int b, double t, double touch, double target) {
  const auto& outline = m.sides.at(m.body_names[0] + ".boundary");
  std::vector<char> free(m.x.size(), 0);
  std::vector<Vec2> normal(m.x.size(), Vec2::Zero());
  for (const Edge& e : outline) {
    const Vec2 d = m.x[e.b] - m.x[e.a];
    const Vec2 n(d(1), -d(0));  // outward: the body lies left of a counter-clockwise edge
    normal[e.a] += n, normal[e.b] += n;
    free[e.a] = free[e.b] = 1;
  }
  for (Index i = 0; i < static_cast<Index>(m.x.size()); ++i) {
    if (!free[i]) continue;
    const Vec2& p = m.x[i];
    bool off = !(scene.geometry == Geometry::Axisymmetric && std::abs(p(0)) <= touch);
    for (const SymmetryPlane& s : scene.symmetry) off = off && std::abs(p(s.axis) - s.at) > touch;
    for (const ContactPair& pair : scene.contact_pairs)
      if (pair.with_die() && pair.body_id == b) off = off && scene.dies[pair.die_id].project(p, t).distance > touch;
    free[i] = off && normal[i].norm() > 0;
    if (free[i]) normal[i].normalize();
  }
  if (std::find(free.begin(), free.end(), 1) == free.end()) return false;
  const std::vector<Vec2> x0 = m.x;
  double delta = 0;
  for (int it = 0; it < 8; ++it) {
    double v = 0, dv = 0;
    for (const Edge& e : outline) {
      const EdgeVolume ev = edge_volume(m.x[e.a], m.x[e.b], scene.geometry);
      v += ev.v;
      if (free[e.a]) dv += ev.da.dot(normal[e.a]);
      if (free[e.b]) dv += ev.db.dot(normal[e.b]);
    }
    if (std::abs(v - target) <= 1e-15 * std::abs(target) || dv == 0) break;
    delta -= (v - target) / dv;
    for (Index i = 0; i < static_cast<Index>(m.x.size()); ++i)
      if (free[i]) m.x[i] = x0[i] + delta * normal[i];
  }
  return true;
}

double body_volume(const Mesh& m, const std::vector<Vec2>& x, Geometry g) {
  double v = 0;
  for (const Edge& e : m.sides.at(m.body_names[0] + ".boundary")) v += edge_volume(x[e.a], x[e.b], g).v;
  return v;
}

double relative(double after, double before) { return before != 0 ? after / before - 1 : after - before; }

}  // namespace

RemeshChange remesh_change(const Scene& before, const RunState& old_state, const RemeshedScene& after) {
  const Totals a = totals(before.mesh, old_state.x, old_state.strain, before.geometry);
  const Totals b = totals(after.scene.mesh, after.state.x, after.state.strain, before.geometry);
  return {relative(b.volume, a.volume), relative(b.integral, a.integral), relative(b.max, a.max)};
}

RemeshedScene remesh_scene(const Scene& scene, const RunState& state, const RemeshRequest& request) {
  const std::vector<int>& bodies = request.bodies;
  if (bodies.size() != request.size.size()) throw std::invalid_argument("remesh_scene: one size per body");
  RemeshedScene out{scene, {}, std::vector<Index>(scene.mesh.num_nodes(), -1), 0, {}};
  Mesh mesh;
  RunState& st = out.state;
  st.time = state.time, st.stroke = state.stroke, st.step = state.step, st.dt = state.dt;
  for (int b = 0; b < scene.mesh.num_bodies(); ++b) {
    BodyPart part = body_part(scene.mesh, state, b);
    const auto listed = std::find(bodies.begin(), bodies.end(), b);
    if (listed != bodies.end()) {
      const double size = request.size[listed - bodies.begin()];
      OutlineOptions o{size, size_field(scene, part, state.time, size, request),
                       request.volume_tolerance, scene.geometry, {}, die_placement(scene, b, state.time, size)};
      for (Index n : request.pinned)
        if (part.node.at(n) >= 0) o.pinned.push_back(part.node[n]);
      OutlineMesh fresh = mesh_outline(part.mesh, part.mesh.x, 0, o);
      if (fresh.subdivided) out.subdivided.push_back(scene.mesh.body_names.at(b));
      const double before = body_volume(part.mesh, part.mesh.x, scene.geometry);
      const double overlap = before - body_volume(fresh.mesh, fresh.mesh.x, scene.geometry);
      if (std::abs(overlap) > 1e-13 * std::abs(before) &&
          restore_volume(fresh.mesh, scene, b, state.time, 1e-3 * size, before))
        out.overlap_restored += overlap / before;
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
  // Within the run's limits, as the case's meshes are (io/scene_reader.cpp):
  // a size from the error at a singular point can refine without bound
  // short of remesh.min_size.
  const Index ne = out.scene.mesh.num_elements(), nn = out.scene.mesh.num_nodes();
  if (ne > scene.max_elements || nn > scene.max_nodes)
    throw InputError(scene.file + ": the new mesh has " + std::to_string(ne) + " elements and " +
                     std::to_string(nn) + " nodes; expected at most run.max_elements = " +
                     std::to_string(scene.max_elements) + " and run.max_nodes = " + std::to_string(scene.max_nodes) +
                     " (raise them in [run], or coarsen the remesh: remesh.element_size, remesh.min_size)");
  return out;
}

RemeshRequest remesh_request(const Scene& scene) {
  RemeshRequest request;
  request.bodies = scene.remesh.bodies;
  for (int b : request.bodies) request.size.push_back(scene.remesh.size.at(b));
  request.volume_tolerance = scene.remesh.volume_tolerance;
  request.die_corner_size = scene.remesh.die_corner_size;
  request.target_error = scene.remesh.target_error;
  request.min_size = scene.remesh.min_size;
  request.max_size = scene.remesh.max_size;
  return request;
}

Scene initial_remesh(const Scene& scene, const std::vector<GaussValues>& rate) {
  RunState start;
  start.x = scene.mesh.x;
  start.strain.assign(scene.mesh.num_elements(), {0, 0, 0, 0});
  start.rate = rate;
  return remesh_scene(scene, start, remesh_request(scene)).scene;
}

}  // namespace rpfem
