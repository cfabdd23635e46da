#include "direct/direct_enforcement.hpp"

#include "contact/friction_treatment.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Dense>

namespace rpfem {

DirectEnforcement::DirectEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc)
    : scene_(scene), disc_(disc) {
  require_friction_treatment(scene, name(), {});
  if (!disc.node_rows_on_dies())
    throw InputError(scene.file + ": key 'contact.dies' = 'mortar': enforcement 'direct' holds a node on a die by "
                     "elimination, one node at a time; expected contact.dies = 'node', or enforcement 'penalty', "
                     "'auglag' or 'ipopt'");
  for (const auto& f : disc.interfaces()) {
    if (f.die < 0)
      throw InputError(scene.file + ": the contact pair '" + f.name + "' is between bodies; enforcement 'direct' "
                       "treats rigid dies only (use 'penalty', 'auglag' or 'ipopt')");
    coulomb_ = coulomb_ || f.friction.kind == FrictionLaw::Kind::Coulomb;
    smoothing_.include(f.friction);
  }
  speed_scale_ = scene.largest_speed();
  if (smoothing_.factor() > 1 && !(speed_scale_ > 0))
    throw InputError(scene.file + ": key 'dies.<name>.friction.a' is relative to the largest prescribed speed, "
                                  "but nothing moves");
  const double size = scene.mesh.size();
  touch_tol_ = settings.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  release_tol_ = settings.real("release_tolerance", 1e-9, Range::nonnegative(), "relative to the largest contact force");
  coulomb_in_newton_ = settings.choice<bool>("coulomb_update", std::string("newton"),
                                             {{"newton", true}, {"passes", false}});
  coulomb_tol_ = settings.real("coulomb_tolerance", 1e-4, Range::positive(),
                               "largest change of a Coulomb friction bound between passes, relative");
}

const FrictionLaw& DirectEnforcement::law(std::size_t i) const {
  return disc_.interfaces()[(*rows_)[i].iface].friction;
}

double DirectEnforcement::smoothing_speed(std::size_t i) const {
  return law(i).smoothing_speed(speed_scale_) * smoothing_.factor();
}

void DirectEnforcement::begin_step(const StepView& v, const std::vector<ContactRow>& rows) {
  rows_ = &rows;
  const auto& ifaces = disc_.interfaces();
  now_.assign(rows.size(), {});
  std::map<std::pair<int, Index>, State> next;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ContactRow& r = rows[i];
    const auto it = state_.find({r.iface, r.key});
    if (it != state_.end()) now_[i] = it->second;
    // Touch: a free node on (or, by round-off, just inside) the die.
    if (!now_[i].in_contact && r.kin.gap0 <= touch_tol_) {
      now_[i] = {true, 0.0};
      touches_.push_back("touch node " + std::to_string(r.key) + " on die " + scene_.dies[ifaces[r.iface].die].name);
    }
    next[{r.iface, r.key}] = now_[i];
  }
  state_ = std::move(next);
  std::vector<char> on(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) on[i] = now_[i].in_contact;
  std::vector<RowArea> area;
  disc_.areas(v, rows, on, area);
  kw_.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) kw_[i] = area[i].kw;
  bound_.assign(rows.size(), 0.0);
  update_bounds(1.0);
  results_.assign(rows.size(), {});
  coulomb_relax_ = 1;
  coulomb_change_ = INFINITY;
  started_ = false;
  fixed_point_ = false;
  merit_bound_.clear();
  tangent_bound_ = bound_;
  set_live();
}

std::map<Index, std::vector<std::size_t>> DirectEnforcement::contact_rows_by_node() const {
  std::map<Index, std::vector<std::size_t>> out;
  for (std::size_t i = 0; i < rows_->size(); ++i)
    if (now_[i].in_contact) out[(*rows_)[i].kin.nodes[0]].push_back(i);
  return out;
}

void DirectEnforcement::set_live() {
  live_.assign(rows_->size(), 0);
  if (!coulomb_in_newton_ || fixed_point_) return;
  for (const auto& [node, ids] : contact_rows_by_node())
    if (ids.size() == 1 && law(ids[0]).kind == FrictionLaw::Kind::Coulomb) live_[ids[0]] = 1;
}

bool DirectEnforcement::fall_back() {
  if (!coulomb_ || !coulomb_in_newton_ || fixed_point_) return false;
  fixed_point_ = true;
  started_ = false;
  merit_bound_.clear();
  set_live();
  return true;
}

void DirectEnforcement::force_nodes(std::vector<Index>& out) const {
  for (std::size_t i = 0; i < live_.size(); ++i)
    if (live_[i]) out.push_back((*rows_)[i].kin.nodes[0]);
}

double DirectEnforcement::update_bounds(double relax) {
  double change = 0, largest = 0;
  for (std::size_t i = 0; i < bound_.size(); ++i) {
    const double B = friction_bound(law(i), now_[i].in_contact, now_[i].normal, kw_[i]);
    change = std::max(change, std::abs(B - bound_[i]));
    largest = std::max(largest, B);
    bound_[i] += relax * (B - bound_[i]);
  }
  return largest > 0 ? change / largest : 0.0;
}

void DirectEnforcement::constraints(const StepView&, std::vector<NodeConstraint>& out) const {
  // v_node . n = v_die . n: the die's normal velocity; the node slides
  // along the tangent.
  for (std::size_t i = 0; i < rows_->size(); ++i)
    if (now_[i].in_contact) {
      const PairKinematics& k = (*rows_)[i].kin;
      out.push_back({k.nodes[0], k.n, k.offset.dot(k.n)});
    }
}

void DirectEnforcement::add_terms(const StepView&, const std::vector<Vec2>& vel, TermSink& sink) const {
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    if (!now_[i].in_contact) continue;
    const PairKinematics& k = (*rows_)[i].kin;
    // Coulomb on a node alone on its die: B = min(mu N, k w) at this
    // iterate's reaction N = n . F_s (Kobayashi, Oh, Altan 1989, eq. 8.18
    // with the normal traction from the nodal reaction). Not at a solve's
    // start (its first residual and tangent): the start iterate breaks the
    // constraints of the nodes that touched, and its reactions are no
    // equilibrium's (50 times the converged ones on the upsetting's face,
    // every bound at the cap k w, and Newton needed 8 or 9 iterations a
    // solve); the last solve's bound serves there.
    const bool live = live_[i] && started_;
    const double N = live ? k.n.dot(sink.element_force(k.nodes[0])) : 0.0;
    const double B = live ? friction_bound(law(i), true, N, kw_[i]) : bound_[i];
    if (sink.needs_hessian()) tangent_bound_[i] = B;
    const double merit = merit_bound_.empty() ? -1.0 : merit_bound_[i];
    if (!(B > 0) && !(merit > 0)) continue;
    RowLaw l;
    l.normal = false;
    l.fixed_bound = B;
    l.merit_bound = merit;
    l.a = smoothing_speed(i);
    const RowTerm term = row_term(k, l, vel);
    add_row_term(sink, k, term);
    // Below the cap, d(friction force)/dv gains (mu / B) g (n^T K_s): the
    // friction gradient g scaled to one newton of N, times the
    // reaction's derivative.
    if (live && sink.needs_hessian() && law(i).mu * N < kw_[i]) {
      std::array<double, 2 * kMaxRowNodes> g;
      expand(k, term, g.data(), nullptr);
      for (int a = 0; a < 2 * k.k; ++a) g[a] *= law(i).mu / B;
      sink.add_force_coupling(k.nodes[0], k.n, k.nodes.data(), k.k, g.data());
    }
  }
  if (sink.needs_hessian()) started_ = true;
}

StepCheck DirectEnforcement::settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) {
  StepCheck out;
  started_ = false;  // the next solve starts anew
  merit_bound_.clear();
  out.events.swap(touches_);
  const auto& rows = *rows_;
  // F is the full nodal force; its normal part at a contact node is the
  // die's normal reaction (friction acts along the tangent only).
  double scale = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    RowResult& r = results_[i];
    r = {};
    if (!now_[i].in_contact) continue;
    r.in_contact = true;
    r.slip = slip_rate(rows[i].kin, vel);
    now_[i].normal = F[rows[i].kin.nodes[0]].dot(rows[i].kin.n);
    // A live Coulomb row's bound is the solve's own (at its reaction).
    if (live_[i]) bound_[i] = friction_bound(law(i), true, now_[i].normal, kw_[i]);
    if (bound_[i] > 0) r.friction = -bound_[i] * arctan_potential(r.slip, smoothing_speed(i)).dpsi;
    scale = std::max(scale, std::abs(now_[i].normal));
  }
  // A node on two dies (a container's corner: wall and bottom) has one
  // nodal reaction for both rows: it is split into each die's normal
  // force, F = sum N_r n_r (least squares; two independent normals span
  // the plane). Before, each row took the whole reaction and each die's
  // load counted the other's: the backward extrusion's container wall
  // carried the corner node's bottom reaction, 0.7 kN of vertical load
  // where the wall's friction alone is 4.8 kN.
  std::vector<char> shared(rows.size(), 0);
  for (const auto& [node, ids] : contact_rows_by_node()) {
    if (ids.size() < 2) continue;
    Eigen::MatrixXd A(2, ids.size());
    for (std::size_t c = 0; c < ids.size(); ++c) A.col(c) = rows[ids[c]].kin.n;
    const Eigen::VectorXd N = A.completeOrthogonalDecomposition().solve(Eigen::Vector2d(F[node]));
    for (std::size_t c = 0; c < ids.size(); ++c) now_[ids[c]].normal = N(c), shared[ids[c]] = 1;
  }
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (shared[i]) scale = std::max(scale, std::abs(now_[i].normal));
  bool released = false;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!now_[i].in_contact) continue;
    // The die pushes the body along +n: a negative normal force is tension.
    if (now_[i].normal < -release_tol_ * scale) {
      now_[i] = {};
      results_[i] = {};
      released = true;
      out.events.push_back("release node " + std::to_string(rows[i].key) + " from die " +
                           scene_.dies[disc_.interfaces()[rows[i].iface].die].name);
    } else {
      // The die's force on the body: the whole nodal reaction (F includes
      // the friction potential's gradient, -friction) plus the friction;
      // at a node shared with another die, its own share.
      const Vec2 t(-rows[i].kin.n(1), rows[i].kin.n(0));
      const Vec2 reaction = shared[i] ? Vec2(now_[i].normal * rows[i].kin.n) : Vec2(F[rows[i].kin.nodes[0]]);
      results_[i].normal = now_[i].normal;
      results_[i].slave_force = reaction + results_[i].friction * t;
    }
  }
  out.resolve = released;
  if (released) {
    std::vector<char> on(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) on[i] = now_[i].in_contact;
    std::vector<RowArea> area;
    disc_.areas(v, rows, on, area);
    for (std::size_t i = 0; i < rows.size(); ++i) kw_[i] = area[i].kw;
    set_live();
  }
  // Coulomb: B = min(mu N, k w) with the new normal forces; solve again
  // until the bounds settle (a fixed point on the normal forces). A pass
  // that does not shrink the change by at least a quarter halves the
  // relaxation (a period-2 oscillation between stick-capped and mu
  // N-bounded nodes otherwise never settles).
  const double previous = coulomb_change_;
  coulomb_change_ = update_bounds(coulomb_relax_);
  if (coulomb_ && coulomb_change_ > coulomb_tol_) {
    out.resolve = true;
    if (coulomb_change_ > 0.75 * previous) coulomb_relax_ = std::max(0.05, 0.5 * coulomb_relax_);
  }
  if (smoothing_.relax()) out.resolve = true;
  for (std::size_t i = 0; i < rows.size(); ++i) state_[{rows[i].iface, rows[i].key}] = now_[i];
  return out;
}

double DirectEnforcement::place_on_surfaces(const StepView& v, std::vector<Vec2>& x) {
  max_placement_ = max_overshoot_ = 0;
  const auto& ifaces = disc_.interfaces();
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    const Index n = (*rows_)[i].kin.nodes[0];
    const DieProjection p = scene_.dies[ifaces[(*rows_)[i].iface].die].project(x[n], v.time);
    if (now_[i].in_contact) {
      // At a sharp corner or a profile end the closest point is the vertex
      // itself; a node there is left where it is.
      if (p.at_vertex) continue;
      max_placement_ = std::max(max_placement_, std::abs(p.distance));
      x[n] = p.point;
    } else if (p.distance < 0) {
      // A free node that crossed the die within the step (landing control
      // predicts the landing from the previous velocity, the midpoint moves
      // with another): placed on the die, the overshoot reported.
      max_overshoot_ = std::max(max_overshoot_, -p.distance);
      x[n] = p.point;
    }
  }
  return std::max(max_placement_, max_overshoot_);
}

void DirectEnforcement::columns(std::vector<NamedValue>& out) const {
  out.push_back({"max_placement", max_placement_});
  out.push_back({"max_overshoot", max_overshoot_});
  if (coulomb_) out.push_back({"coulomb_change", coulomb_change_});
}

}  // namespace rpfem
