#include "penalty/penalty_formulation.hpp"

#include <algorithm>
#include <cmath>

#include "fem/edge_weights.hpp"
#include "model/boundary.hpp"
#include "penalty/roles.hpp"

namespace rpfem {

namespace {

// A node that landed within a step ends it this close to its master (the
// linearized geometry of the step), relative to the element size.
constexpr double kLandingTolerance = 1e-3;


}  // namespace

PenaltyContact::PenaltyContact(const Scene& scene, CaseSection settings) : scene_(scene) {
  if (scene.contact_pairs.empty())
    throw InputError(scene.file + ": formulation 'penalty' needs at least one [[contact_pairs]] entry");
  const double size = scene.mesh.size();
  speed_scale_ = scene.largest_speed();
  if (!(speed_scale_ > 0)) throw InputError(scene.file + ": formulation 'penalty' scales beta by the largest "
                                                         "prescribed speed, but nothing moves");
  const double beta_factor = settings.real("beta_factor", 1.0, Range::positive(), "times the default beta");
  const auto beta = settings.optional_real("beta", Range::positive(), "MPa s/mm (replaces the default)");
  two_pass_ = settings.flag("two_pass", false);
  gap_correction_ = settings.flag("gap_correction", true);
  touch_tol_ = settings.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  release_tol_ = settings.real("release_tolerance", 1e-9, Range::nonnegative(), "relative to the largest contact force");
  switch_tol_ = settings.real("switch_tolerance", 3e-2, Range::positive(), "relative to the element size");
  capture_ = settings.real("capture", 1.0, Range::positive(), "search reach, relative to the mean master edge length");
  sym_tol_ = 1e-9 * size;

  for (const auto& pair : scene.contact_pairs) {
    Interface f;
    f.side[0] = ContactSurface::from_sides(scene.mesh, pair.sides);
    f.sigma_ref = scene.bodies[pair.body_id].law.yield(0.0);
    if (pair.with_die()) {
      f.name = pair.body + "-" + pair.die;
      f.die = pair.die_id;
      f.friction = scene.dies[f.die].friction;
      f.h = mean_edge_length(scene.mesh.x, f.side[0]);
    } else {
      f.name = pair.body + "-" + pair.with_body;
      f.side[1] = ContactSurface::from_sides(scene.mesh, pair.with_sides);
      f.friction = pair.friction;
      f.sigma_ref = std::min(f.sigma_ref, scene.bodies[pair.with_body_id].law.yield(0.0));
      const double h0 = mean_edge_length(scene.mesh.x, f.side[0]), h1 = mean_edge_length(scene.mesh.x, f.side[1]);
      f.slave = h1 < h0 ? 1 : 0;  // the finer surface starts as the slave
      f.h = std::min(h0, h1);
      any_bodies_ = true;
    }
    // Default: 1e4 times an element's stiffness at the reference strain
    // rate (see the header); beta_factor scales it, beta replaces it.
    f.beta_hat = beta ? *beta : beta_factor * 1e4 * f.sigma_ref * size / (speed_scale_ * f.h);
    for (int s = 0; s < 2; ++s) f.active[s].assign(f.side[s].nodes.size(), 0);
    coulomb_ = coulomb_ || f.friction.kind == FrictionLaw::Kind::Coulomb;
    if (f.friction.kind != FrictionLaw::Kind::None) a_factor_ = std::max(a_factor_, 0.1 / f.friction.a_relative);
    ifaces_.push_back(std::move(f));
  }
}

void PenaltyContact::begin_step(const StepView& v) {
  pairs_.clear();
  master_penetration_ = 0;
  const auto& x = *v.x;
  for (int i = 0; i < static_cast<int>(ifaces_.size()); ++i) {
    Interface& f = ifaces_[i];
    if (f.die >= 0) {
      collect_pairs(v, i, 0, {});
      continue;
    }
    // Each side's nodes searched once on the other side: the hits decide
    // the roles (one pass) and make the slave's pairs.
    const double capture = capture_ * f.h;
    const SegmentGrid g0(x, f.side[0], capture), g1(x, f.side[1], capture);
    const auto hits0 = find_segments(x, f.side[0], f.side[1], g1, capture);
    const auto hits1 = find_segments(x, f.side[1], f.side[0], g0, capture);
    if (two_pass_) {
      collect_pairs(v, i, 0, hits0);
      collect_pairs(v, i, 1, hits1);
      continue;
    }
    const double tol = switch_tol_ * f.h;
    const Penetrations from0 = count_penetrations(hits0, tol), from1 = count_penetrations(hits1, tol);
    const int slave = f.switched_step == v.step ? f.slave : hallquist_slave(f.slave, from0, from1, f.switch_guard);
    // What one pass lets through: the master's nodes inside the slave.
    master_penetration_ = std::max(master_penetration_, (slave == 0 ? from1 : from0).deepest / f.h);
    if (slave != f.slave) {
      std::fill(f.active[f.slave].begin(), f.active[f.slave].end(), 0);
      f.slave = slave;
      f.switch_guard = (slave == 0 ? from0 : from1).deepest;
      f.switched_step = v.step;
      ++role_switches_;
      events_.push_back("interface " + f.name + ": roles switch, the slave is now " +
                        scene_.mesh.body_names[f.side[slave].body]);
    }
    collect_pairs(v, i, slave, slave == 0 ? hits0 : hits1);
  }
  set_laws(v);
  max_penetration_ = max_penetration_rel_ = 0;
  for (const Pair& p : pairs_)
    if (p.kin.gap0 < 0) {
      max_penetration_ = std::max(max_penetration_, -p.kin.gap0);
      max_penetration_rel_ = std::max(max_penetration_rel_, -p.kin.gap0 / p.h);
    }
}

void PenaltyContact::collect_pairs(const StepView& v, int iface, int side,
                                   const std::vector<std::optional<SegmentHit>>& hits) {
  Interface& f = ifaces_[iface];
  const auto& x = *v.x;
  const ContactSurface& S = f.side[side];
  for (int l = 0; l < static_cast<int>(S.nodes.size()); ++l) {
    const Index n = S.nodes[l];
    char& state = f.active[side][l];
    Pair p;
    p.iface = iface;
    p.side = side;
    p.local = l;
    if (f.die >= 0) {
      p.kin = die_pair(scene_.dies[f.die], n, x, v.time);
    } else {
      const auto& hit = hits[l];
      if (!hit) {
        if (state) {
          state = 0;
          events_.push_back("node " + std::to_string(n) + " leaves the master surface of " + f.name);
        }
        continue;
      }
      const Edge& e = f.side[1 - side].edges[hit->edge];
      p.master_element = e.element;
      p.kin = segment_pair(n, e, *hit);
    }
    // The gap where the solved velocity moves the nodes from (the start of
    // the step, in the midpoint scheme's half-step solve).
    if (v.x_from && v.x_from != v.x)
      set_gap_from(p.kin, x, *v.x_from, v.time, v.time_from, f.die >= 0 ? &scene_.dies[f.die] : nullptr);
    // An instantaneous solve anticipates no landing: only nodes touching
    // now (to within what a landing leaves, kLandingTolerance of the
    // element size) take part, and only a penetration is corrected over dt.
    if (!v.moves) {
      p.free = p.kin.gap0 > kLandingTolerance * f.h;
      p.kin.gap_from = std::min(p.kin.gap_from, 0.0);
    }
    if (!state && p.kin.gap0 <= touch_tol_) {
      state = 1;
      events_.push_back("touch node " + std::to_string(n) + " on " + f.name);
    }
    pairs_.push_back(p);
  }
}

void PenaltyContact::set_laws(const StepView& v) {
  const auto& x = *v.x;
  // Per interface side: each surface node's lumped area (all its edges:
  // the penalty weight), its area over edges with both ends active (the
  // friction bound's), the shear-yield bound and the local element size.
  struct NodeData {
    double w = 0, w_active = 0, kw = 0, len = 0;
    int edges = 0;
  };
  std::vector<std::array<std::vector<NodeData>, 2>> data(ifaces_.size());
  for (std::size_t i = 0; i < ifaces_.size(); ++i)
    for (int s = 0; s < 2; ++s) {
      const Interface& f = ifaces_[i];
      const ContactSurface& S = f.side[s];
      auto& d = data[i][s];
      d.assign(S.nodes.size(), {});
      for (const Edge& e : S.edges) {
        const int a = S.local(e.a), b = S.local(e.b);
        const auto w = edge_weights(x[e.a], x[e.b], v.geometry);
        const double L = (x[e.b] - x[e.a]).norm();
        d[a].w += w[0], d[b].w += w[1];
        d[a].len += L, d[b].len += L;
        ++d[a].edges, ++d[b].edges;
        if (f.active[s][a] && f.active[s][b]) {
          const double k = (*v.flow_stress)[e.element] / std::sqrt(3.0);  // shear yield stress (von Mises)
          d[a].w_active += w[0], d[b].w_active += w[1];
          d[a].kw += k * w[0], d[b].kw += k * w[1];
        }
      }
    }
  for (Pair& p : pairs_) {
    const Interface& f = ifaces_[p.iface];
    const NodeData& d = data[p.iface][p.side][p.local];
    p.weight = d.w;
    p.h = d.edges ? d.len / d.edges : f.h;
    p.law.beta = f.beta_hat * d.w;
    p.law.inv_dt = gap_correction_ && v.dt > 0 ? 1.0 / v.dt : 0.0;
    p.law.one_sided = one_sided();
    p.law.kind = f.friction.kind;
    p.law.m = f.friction.m;
    p.law.mu = f.friction.mu;
    p.law.a = f.friction.a_relative * speed_scale_;
    // The sticking bound k w of the softer side: the master element's k
    // over the slave node's area is the other candidate.
    double kw = d.kw;
    if (p.master_element >= 0) kw = std::min(kw, (*v.flow_stress)[p.master_element] / std::sqrt(3.0) * d.w_active);
    // Two-pass: each pass carries half the friction of the interface
    // (Coulomb's share follows from each pass's own normal force).
    p.law.k_weight = two_pass_ && f.die < 0 ? 0.5 * kw : kw;
  }
}

PairResult PenaltyContact::evaluate(const Pair& p, const std::vector<Vec2>& vel, bool hess) const {
  std::array<Vec2, 3> v{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  for (int a = 0; a < p.kin.k; ++a) v[a] = vel[p.kin.nodes[a]];
  PairLaw law = p.law;
  law.a *= a_factor_;
  law.merit_bound = p.merit_bound;
  // The friction factor acts on nodes in contact (Coulomb's bound follows
  // the normal force by itself).
  if (law.kind == FrictionLaw::Kind::Factor && !active(p)) law.kind = FrictionLaw::Kind::None;
  // A pair in contact keeps its normal stiffness in the Newton matrix when
  // an iterate lifts it off (a body held only by contacts would float).
  law.keep_stiffness = active(p);
  return pair_terms(p.kin, law, v, hess);
}

void PenaltyContact::anchor_merit(const StepView&, const std::vector<Vec2>& vel) {
  for (Pair& p : pairs_) {
    p.merit_bound = -1;
    if (engaged(p)) p.merit_bound = evaluate(p, vel, false).bound;
  }
}

std::array<Vec2, 3> PenaltyContact::pair_forces(const Pair& p) const {
  std::array<Vec2, 3> f{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  for (int a = 0; a < p.kin.k; ++a) f[a] = -Vec2(p.res.grad[2 * a], p.res.grad[2 * a + 1]);
  return f;
}

void PenaltyContact::couplings(const StepView&, std::vector<std::vector<Index>>& out) const {
  for (const Pair& p : pairs_)
    if (engaged(p) && p.kin.k > 1) out.push_back({p.kin.nodes.begin(), p.kin.nodes.begin() + p.kin.k});
}

void PenaltyContact::add_terms(const StepView&, const std::vector<Vec2>& vel, TermSink& sink) const {
  for (const Pair& p : pairs_) {
    if (!engaged(p)) continue;
    const PairResult r = evaluate(p, vel, sink.needs_hessian());
    sink.add(p.kin.nodes.data(), p.kin.k, r.energy, r.grad.data(), r.hess.data());
  }
}

StepCheck PenaltyContact::check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) {
  if (one_sided()) return check_one_sided(v, vel);
  StepCheck out;
  out.events.swap(events_);
  double scale = 0;
  for (Pair& p : pairs_) {
    p.res = active(p) ? evaluate(p, vel, false) : PairResult{};
    scale = std::max(scale, std::abs(p.res.normal_force));
  }
  active_pairs_ = 0;
  bool released = false, touched = false;
  for (Pair& p : pairs_) {
    if (!active(p)) {
      // A free slave node that this velocity would carry into its master
      // within the step (it touches in less than the step, or after
      // limit_dt's landing prediction from the previous velocity missed):
      // in contact now, solve again.
      // A node released in this step stays free for it (no flip-flop).
      // Only with the gap correction: without it an active pair keeps its
      // gap, and a node made active short of its master would stay there.
      if (!gap_correction_ || p.changed || !(v.dt > 0)) continue;
      const double end_gap = p.kin.gap_from + v.dt * gap_rate(p.kin, vel);
      if (end_gap < -touch_tol_) {
        set_active(p, true);
        touched = true;
        out.events.push_back("touch node " + std::to_string(p.kin.nodes[0]) + " on " + ifaces_[p.iface].name +
                             " (within the step)");
      }
      continue;
    }
    // The penalty pushes the slave out along +n: a negative normal force
    // pulls the bodies together.
    if (p.res.normal_force < -release_tol_ * scale) {
      set_active(p, false);
      p.changed = true;
      p.res = PairResult{};
      released = true;
      out.events.push_back("release node " + std::to_string(p.kin.nodes[0]) + " from " + ifaces_[p.iface].name);
    } else {
      ++active_pairs_;
    }
  }
  if (released || touched) {
    set_laws(v);
    out.resolve = true;
  }
  // Continuation in the friction smoothing at the run's first solve.
  continue_smoothing(out);
  return out;
}

StepCheck PenaltyContact::check_one_sided(const StepView& v, const std::vector<Vec2>& vel) {
  // Every candidate pair carries the one-sided penalty: the contact state
  // only reports the pairs that press (N > 0), switches the friction
  // factor on and off and sets the contact area of the sticking bound k w
  // (which caps Coulomb's mu N too). A state change matters only to
  // friction, so only then is the step solved again; a node changes state
  // at most once per solve of the step (no flip-flop).
  StepCheck out;
  out.events.swap(events_);
  active_pairs_ = 0;
  bool changed = false;
  for (Pair& p : pairs_) {
    p.res = p.free ? PairResult{} : evaluate(p, vel, false);
    const bool pressing = p.res.normal_force > 0;
    if (pressing != static_cast<bool>(active(p)) && !p.changed) {
      set_active(p, pressing);
      p.changed = true;
      changed = changed || p.law.kind != FrictionLaw::Kind::None;
      out.events.push_back((pressing ? "touch node " : "release node ") + std::to_string(p.kin.nodes[0]) +
                           (pressing ? " on " : " from ") + ifaces_[p.iface].name);
      if (changed) p.res = evaluate(p, vel, false);
    }
    active_pairs_ += active(p) ? 1 : 0;
  }
  if (changed) {
    set_laws(v);
    out.resolve = true;
  }
  continue_smoothing(out);
  return out;
}

void PenaltyContact::continue_smoothing(StepCheck& out) {
  // Continuation in the friction smoothing at the run's first solve.
  if (a_factor_ > 1) {
    a_factor_ = std::max(1.0, a_factor_ / 10);
    out.resolve = true;
  }
}

std::optional<double> PenaltyContact::limit_dt(const StepView& v, const std::vector<Vec2>& vel) const {
  // One-sided: a node that would land within the step is pushed onto its
  // master at the end of the step by its own term; no landing cut needed.
  if (one_sided()) return std::nullopt;
  std::optional<double> limit;
  for (const Pair& p : pairs_) {
    if (active(p) || p.kin.gap0 <= 0) continue;
    const double closing = -gap_rate(p.kin, vel);
    if (closing <= 0) continue;
    const double t = p.kin.gap0 / closing;
    if (t < v.dt && (!limit || t < *limit)) limit = t;
  }
  if (limit && *limit < 1e-6 * v.dt) return std::nullopt;
  return limit;
}

std::optional<double> PenaltyContact::reference_speed(const std::string& name) const {
  for (const auto& d : scene_.dies)
    if (d.name == name) return d.motion.max_speed();
  return std::nullopt;
}

void PenaltyContact::contact_forces(const StepView&, const std::vector<Vec2>& vel, const std::vector<Vec2>&,
                                    std::vector<Vec2>& out) const {
  out.assign(vel.size(), Vec2::Zero());
  for (const Pair& p : pairs_) {
    if (!engaged(p)) continue;
    const auto f = pair_forces(p);
    for (int a = 0; a < p.kin.k; ++a) out[p.kin.nodes[a]] += f[a];
  }
}

std::vector<std::string> PenaltyContact::load_names() const {
  std::vector<std::string> n;
  for (const auto& d : scene_.dies) n.push_back(d.name);
  return n;
}

std::vector<Vec2> PenaltyContact::loads(const StepView& v, const std::vector<Vec2>&) const {
  // A die's load: the force it exerts on the bodies (as in `direct`).
  std::vector<Vec2> out;
  for (int d = 0; d < static_cast<int>(scene_.dies.size()); ++d) {
    Vec2 sum = Vec2::Zero();
    std::vector<Index> nodes;
    for (const Pair& p : pairs_)
      if (engaged(p) && ifaces_[p.iface].die == d && p.res.normal_force != 0) {
        sum += pair_forces(p)[0];
        nodes.push_back(p.kin.nodes[0]);
      }
    out.push_back(sum.cwiseProduct(symmetry_load_factor(scene_.symmetry, *v.x, nodes, sym_tol_)));
  }
  return out;
}

void PenaltyContact::node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const {
  const std::size_t n = v.x->size();
  auto& pr = out["contact_pressure"];
  auto& sh = out["contact_shear"];
  auto& slip = out["slip_velocity"];
  auto& gap = out["contact_gap"];
  for (auto* f : {&pr, &sh, &slip, &gap}) f->assign(n, 0.0);
  for (const Pair& p : pairs_) {
    const Index s = p.kin.nodes[0];
    gap[s] = p.kin.gap0;
    if (!engaged(p) || !(p.weight > 0)) continue;
    pr[s] += p.res.normal_force / p.weight;
    sh[s] += p.res.friction / p.weight;
    slip[s] = p.res.gamma_t;
  }
}

std::vector<std::string> PenaltyContact::report_names() const {
  std::vector<std::string> n{"contact_pairs", "max_penetration", "max_penetration_rel"};
  if (any_bodies_) n.insert(n.end(), {"master_penetration_rel", "force_imbalance", "role_switches"});
  for (const auto& b : scene_.mesh.body_names)
    for (const char* q : {".contact_Fx", ".contact_Fy", ".normal_force", ".friction_force"}) n.push_back(b + q);
  return n;
}

std::vector<double> PenaltyContact::report() const {
  const int nb = scene_.mesh.num_bodies();
  std::vector<Vec2> resultant(nb, Vec2::Zero());
  std::vector<double> normal(nb, 0.0), friction(nb, 0.0);
  // Per body-body interface, the resultant on each side (action-reaction).
  std::vector<std::array<Vec2, 2>> side_force(ifaces_.size(), {Vec2::Zero(), Vec2::Zero()});
  for (const Pair& p : pairs_) {
    if (!engaged(p)) continue;
    const auto f = pair_forces(p);
    for (int a = 0; a < p.kin.k; ++a) {
      const int b = scene_.mesh.node_body[p.kin.nodes[a]];
      resultant[b] += f[a];
      const bool slave = a == 0;
      side_force[p.iface][slave ? p.side : 1 - p.side] += f[a];
    }
    const int bs = scene_.mesh.node_body[p.kin.nodes[0]];
    normal[bs] += p.res.normal_force;
    friction[bs] += std::abs(p.res.friction);
    if (p.kin.k == 3) {
      const int bm = scene_.mesh.node_body[p.kin.nodes[1]];
      normal[bm] += p.res.normal_force;
      friction[bm] += std::abs(p.res.friction);
    }
  }
  std::vector<double> r{double(active_pairs_), max_penetration_, max_penetration_rel_};
  if (any_bodies_) {
    double imbalance = 0;
    for (std::size_t i = 0; i < ifaces_.size(); ++i) {
      if (ifaces_[i].die >= 0) continue;
      const double big = std::max(side_force[i][0].norm(), side_force[i][1].norm());
      if (big > 0) imbalance = std::max(imbalance, (side_force[i][0] + side_force[i][1]).norm() / big);
    }
    r.push_back(master_penetration_);
    r.push_back(imbalance);
    r.push_back(role_switches_);
  }
  for (int b = 0; b < nb; ++b) {
    // In axisymmetry radial forces cancel around the circumference.
    r.push_back(scene_.geometry == Geometry::Axisymmetric ? 0.0 : resultant[b](0));
    r.push_back(resultant[b](1));
    r.push_back(normal[b]);
    r.push_back(friction[b]);
  }
  return r;
}

std::vector<NamedValue> PenaltyContact::derived() const {
  std::vector<NamedValue> out{{"penalty.speed_scale_mm_s", speed_scale_}, {"penalty.touch_tolerance_mm", touch_tol_}};
  for (const auto& f : ifaces_) {
    out.push_back({"penalty." + f.name + ".beta_MPa_s_mm", f.beta_hat});
    out.push_back({"penalty." + f.name + ".element_size_mm", f.h});
    out.push_back({"penalty." + f.name + ".sigma_ref_MPa", f.sigma_ref});
  }
  return out;
}

}  // namespace rpfem
