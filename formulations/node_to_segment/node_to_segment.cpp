#include "node_to_segment/node_to_segment.hpp"

#include <algorithm>
#include <cmath>

#include "fem/edge_weights.hpp"
#include "node_to_segment/roles.hpp"

namespace rpfem {

NodeToSegment::NodeToSegment(const Scene& scene, CaseSection settings, bool two_pass)
    : scene_(scene), two_pass_(two_pass) {
  switch_tol_ = settings.real("switch_tolerance", 3e-2, Range::positive(),
                              "relative to the element size (one pass: the penetration that switches roles)");
  capture_ = settings.real("capture", 1.0, Range::positive(), "search reach, relative to the mean master edge length");
  for (const auto& pair : scene.contact_pairs) {
    ContactInterface f;
    Sides s;
    s.side[0] = ContactSurface::from_sides(scene.mesh, pair.sides);
    f.bodies[0] = pair.body_id;
    f.sigma_ref = scene.bodies[pair.body_id].law.yield(0.0);
    if (pair.with_die()) {
      f.name = pair.body + "-" + pair.die;
      f.die = pair.die_id;
      f.friction = scene.dies[f.die].friction;
      f.h = mean_edge_length(scene.mesh.x, s.side[0]);
    } else {
      f.name = pair.body + "-" + pair.with_body;
      f.bodies[1] = pair.with_body_id;
      s.side[1] = ContactSurface::from_sides(scene.mesh, pair.with_sides);
      f.friction = pair.friction;
      f.sigma_ref = std::min(f.sigma_ref, scene.bodies[pair.with_body_id].law.yield(0.0));
      const double h0 = mean_edge_length(scene.mesh.x, s.side[0]), h1 = mean_edge_length(scene.mesh.x, s.side[1]);
      s.slave = h1 < h0 ? 1 : 0;  // the finer surface starts as the slave
      f.h = std::min(h0, h1);
      any_bodies_ = true;
    }
    for (const Edge& e : s.side[f.die < 0 && s.slave == 1 ? 1 : 0].edges) {
      const auto w = edge_weights(scene.mesh.x[e.a], scene.mesh.x[e.b], scene.geometry);
      f.area += w[0] + w[1];
    }
    ifaces_.push_back(std::move(f));
    sides_.push_back(std::move(s));
  }
}

void NodeToSegment::rows(const StepView& v, std::vector<ContactRow>& out, std::vector<std::string>& events) {
  out.clear();
  master_penetration_ = 0;
  const auto& x = *v.x;
  for (int i = 0; i < static_cast<int>(ifaces_.size()); ++i) {
    const ContactInterface& f = ifaces_[i];
    Sides& s = sides_[i];
    if (f.die >= 0) {
      add_rows(v, i, 0, {}, out);
      continue;
    }
    // Each side's nodes searched once on the other side: the hits decide
    // the roles (one pass) and make the slave's rows.
    const double capture = capture_ * f.h;
    const SegmentGrid g0(x, s.side[0], capture), g1(x, s.side[1], capture);
    const auto hits0 = find_segments(x, s.side[0], s.side[1], g1, capture);
    const auto hits1 = find_segments(x, s.side[1], s.side[0], g0, capture);
    if (two_pass_) {
      add_rows(v, i, 0, hits0, out);
      add_rows(v, i, 1, hits1, out);
      continue;
    }
    const double tol = switch_tol_ * f.h;
    const Penetrations from0 = count_penetrations(hits0, tol), from1 = count_penetrations(hits1, tol);
    const int slave = s.switched_step == v.step ? s.slave : hallquist_slave(s.slave, from0, from1, s.switch_guard);
    // What one pass lets through: the master's nodes inside the slave.
    master_penetration_ = std::max(master_penetration_, (slave == 0 ? from1 : from0).deepest / f.h);
    if (slave != s.slave) {
      s.slave = slave;
      s.switch_guard = (slave == 0 ? from0 : from1).deepest;
      s.switched_step = v.step;
      ++role_switches_;
      events.push_back("interface " + f.name + ": roles switch, the slave is now " +
                       scene_.mesh.body_names[s.side[slave].body]);
    }
    add_rows(v, i, slave, slave == 0 ? hits0 : hits1, out);
  }
}

void NodeToSegment::add_rows(const StepView& v, int iface, int side,
                             const std::vector<std::optional<SegmentHit>>& hits, std::vector<ContactRow>& out) const {
  const ContactInterface& f = ifaces_[iface];
  const ContactSurface& S = sides_[iface].side[side];
  const auto& x = *v.x;
  // Each slave node's lumped area over all its surface edges and its local
  // element size (the mean length of those edges).
  std::vector<double> w(S.nodes.size(), 0.0), len(S.nodes.size(), 0.0);
  std::vector<int> edges(S.nodes.size(), 0);
  for (const Edge& e : S.edges) {
    const int a = S.local(e.a), b = S.local(e.b);
    const auto ew = edge_weights(x[e.a], x[e.b], v.geometry);
    const double L = (x[e.b] - x[e.a]).norm();
    w[a] += ew[0], w[b] += ew[1];
    len[a] += L, len[b] += L;
    ++edges[a], ++edges[b];
  }
  for (int l = 0; l < static_cast<int>(S.nodes.size()); ++l) {
    const Index n = S.nodes[l];
    ContactRow r;
    r.iface = iface;
    r.key = n;
    r.weight = w[l];
    r.h = edges[l] ? len[l] / edges[l] : f.h;
    if (f.die >= 0) {
      r.kin = die_pair(scene_.dies[f.die], n, x, v.time);
      r.gap_normal = r.kin.n;
    } else {
      if (!hits[l]) continue;
      const Edge& e = sides_[iface].side[1 - side].edges[hits[l]->edge];
      r.master_element = e.element;
      r.kin = segment_pair(n, e, *hits[l]);
      const Vec2 d = x[e.b] - x[e.a];
      r.gap_normal = hits[l]->at_vertex ? r.kin.n : Vec2(d(1), -d(0)).normalized();  // outward: body on the left
      if (two_pass_) r.friction_share = 0.5;  // each pass carries half the interface's friction
    }
    // The gap where the solved velocity moves the nodes from (the start of
    // the step, in the midpoint scheme's half-step solve).
    if (v.x_from && v.x_from != v.x)
      set_gap_from(r.kin, x, *v.x_from, v.time, v.time_from, f.die >= 0 ? &scene_.dies[f.die] : nullptr);
    out.push_back(r);
  }
}

void NodeToSegment::areas(const StepView& v, const std::vector<ContactRow>& rows, const std::vector<char>& in_contact,
                          std::vector<RowArea>& out) const {
  const auto& x = *v.x;
  // Per interface side: which surface nodes are in contact, then each
  // node's area and k w over its edges with both ends in contact.
  std::vector<std::array<std::vector<char>, 2>> on(ifaces_.size());
  std::vector<std::array<std::vector<RowArea>, 2>> node(ifaces_.size());
  for (std::size_t i = 0; i < ifaces_.size(); ++i)
    for (int s = 0; s < 2; ++s) {
      on[i][s].assign(sides_[i].side[s].nodes.size(), 0);
      node[i][s].assign(sides_[i].side[s].nodes.size(), {});
    }
  auto side_of = [&](const ContactRow& r) {
    return scene_.mesh.node_body[r.key] == ifaces_[r.iface].bodies[0] ? 0 : 1;
  };
  for (std::size_t j = 0; j < rows.size(); ++j)
    if (in_contact[j]) {
      const int s = side_of(rows[j]);
      on[rows[j].iface][s][sides_[rows[j].iface].side[s].local(rows[j].key)] = 1;
    }
  for (std::size_t i = 0; i < ifaces_.size(); ++i)
    for (int s = 0; s < 2; ++s) {
      const ContactSurface& S = sides_[i].side[s];
      for (const Edge& e : S.edges) {
        const int a = S.local(e.a), b = S.local(e.b);
        if (!on[i][s][a] || !on[i][s][b]) continue;
        const auto w = edge_weights(x[e.a], x[e.b], v.geometry);
        const double k = (*v.flow_stress)[e.element] / std::sqrt(3.0);  // shear yield stress (von Mises)
        node[i][s][a].area += w[0], node[i][s][b].area += w[1];
        node[i][s][a].kw += k * w[0], node[i][s][b].kw += k * w[1];
      }
    }
  out.assign(rows.size(), {});
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const ContactRow& r = rows[j];
    const int s = side_of(r);
    RowArea a = node[r.iface][s][sides_[r.iface].side[s].local(r.key)];
    // The sticking bound of the softer side: the master element's k over
    // the slave node's area is the other candidate.
    if (r.master_element >= 0) a.kw = std::min(a.kw, (*v.flow_stress)[r.master_element] / std::sqrt(3.0) * a.area);
    a.kw *= r.friction_share;
    out[j] = a;
  }
}

void NodeToSegment::columns(std::vector<NamedValue>& out) const {
  if (!any_bodies_) return;
  out.push_back({"master_penetration_rel", master_penetration_});
  out.push_back({"role_switches", double(role_switches_)});
}

}  // namespace rpfem
