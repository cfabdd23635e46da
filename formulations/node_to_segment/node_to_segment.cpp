#include "node_to_segment/node_to_segment.hpp"

#include <algorithm>
#include <cmath>

#include "node_to_segment/roles.hpp"

namespace rpfem {

NodeToSegment::NodeToSegment(const Scene& scene, CaseSection settings, bool two_pass)
    : scene_(scene), surfaces_(scene), two_pass_(two_pass) {
  switch_tol_ = settings.real("switch_tolerance", 3e-2, Range::positive(),
                              "relative to the element size (one pass: the penetration that switches roles)");
  capture_ = settings.real("capture", 1.0, Range{SegmentGrid::kCaptureMin, SegmentGrid::kCaptureMax}, "search reach, relative to the mean master edge length");
  for (int i = 0; i < static_cast<int>(surfaces_.interfaces().size()); ++i) roles_.push_back({surfaces_.finer(i)});
}

bool NodeToSegment::overconstrains() const {
  if (!two_pass_) return false;
  for (const auto& f : surfaces_.interfaces())
    if (f.die < 0) return true;
  return false;
}

void NodeToSegment::rows(const StepView& v, std::vector<ContactRow>& out, std::vector<std::string>& events) {
  out.clear();
  master_penetration_ = 0;
  const auto& x = *v.x;
  for (int i = 0; i < static_cast<int>(surfaces_.interfaces().size()); ++i) {
    const ContactInterface& f = surfaces_.interfaces()[i];
    Roles& s = roles_[i];
    if (f.die >= 0) {
      surfaces_.add_die_rows(v, i, out);
      continue;
    }
    // Each side's nodes searched once on the other side: the hits decide
    // the roles (one pass) and make the slave's rows.
    const double capture = capture_ * f.h;
    const ContactSurface &s0 = surfaces_.side(i, 0), &s1 = surfaces_.side(i, 1);
    const SegmentGrid g0(x, s0, capture), g1(x, s1, capture);
    const auto hits0 = find_segments(x, s0, s1, g1, capture);
    const auto hits1 = find_segments(x, s1, s0, g0, capture);
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
                       scene_.mesh.body_names[surfaces_.side(i, slave).body]);
    }
    add_rows(v, i, slave, slave == 0 ? hits0 : hits1, out);
  }
}

void NodeToSegment::add_rows(const StepView& v, int iface, int side,
                             const std::vector<std::optional<SegmentHit>>& hits, std::vector<ContactRow>& out) const {
  const ContactInterface& f = surfaces_.interfaces()[iface];
  const ContactSurface& S = surfaces_.side(iface, side);
  const ContactSurface& M = surfaces_.side(iface, 1 - side);
  const auto& x = *v.x;
  std::vector<double> w, h;
  surfaces_.node_sizes(x, S, v.geometry, f.h, w, h);
  for (int l = 0; l < static_cast<int>(S.nodes.size()); ++l) {
    if (!hits[l]) continue;
    ContactRow r;
    r.iface = iface;
    r.key = S.nodes[l];
    r.weight = w[l];
    r.h = h[l];
    const Edge& e = M.edges[hits[l]->edge];
    r.master_element = e.element;
    r.kin = segment_pair(S.nodes[l], e, *hits[l]);
    r.gap_normal = hits[l]->at_vertex ? r.kin.n : outward(x[e.b] - x[e.a]);
    if (two_pass_) r.friction_share = 0.5;  // each pass carries half the interface's friction
    surfaces_.set_gap_from(v, r);
    out.push_back(r);
  }
}

void NodeToSegment::columns(const StepView*, std::vector<NamedValue>& out) const {
  if (!surfaces_.any_bodies()) return;
  out.push_back({"master_penetration_rel", master_penetration_});
  out.push_back({"role_switches", double(role_switches_)});
}

}  // namespace rpfem
