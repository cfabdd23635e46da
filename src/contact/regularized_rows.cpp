#include "contact/regularized_rows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "model/scene.hpp"

namespace rpfem {

std::vector<double> default_beta_hat(const Scene& scene, const ContactDiscretization& disc, double factor,
                                     std::optional<double> beta) {
  const double size = scene.mesh.size(), speed = scene.largest_speed();
  if (!(speed > 0))
    throw InputError(scene.file + ": the contact penalty is scaled by the largest prescribed speed, but nothing moves");
  std::vector<double> out;
  for (const auto& f : disc.interfaces()) out.push_back(beta ? *beta : factor * 1e4 * f.sigma_ref * size / (speed * f.h));
  return out;
}

void RegularizedEnforcement::derived_betas(const std::string& name, std::vector<NamedValue>& out) const {
  const auto& s = rows_.settings();
  out.push_back({name + ".speed_scale_mm_s", s.speed_scale});
  out.push_back({name + ".touch_tolerance_mm", s.touch_tol});
  for (std::size_t i = 0; i < disc_.interfaces().size(); ++i) {
    const auto& f = disc_.interfaces()[i];
    out.push_back({name + "." + f.name + ".beta_MPa_s_mm", s.beta_hat[i]});
    out.push_back({name + "." + f.name + ".element_size_mm", f.h});
    out.push_back({name + "." + f.name + ".sigma_ref_MPa", f.sigma_ref});
  }
  if (s.adapt.on) out.push_back({name + ".beta_max_factor", s.adapt.max_factor});
}

void RegularizedEnforcement::adaptive_columns(std::vector<NamedValue>& out) const {
  if (!rows_.settings().adapt.on) return;
  out.push_back({"penalty_factor", rows_.adaptive().largest_factor()});
  out.push_back({"penalty_raises", double(rows_.adaptive().raises())});
}

std::optional<std::string> RegularizedEnforcement::retune() {
  const PenaltyRaise r = rows_.raise_penalty();
  if (r.rows == 0) return std::nullopt;
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "penetration %.2g of the element size, above run.penetration_tolerance: solved again with the "
                "penalty of %d row(s) raised (largest factor %.3g)",
                r.depth, r.rows, r.largest_factor);
  return std::string(buf);
}

RegularizedRows::RegularizedRows(const ContactDiscretization& disc, RegularizedSettings s)
    : disc_(disc), s_(std::move(s)), adaptive_(s_.adapt) {
  for (const auto& f : disc.interfaces()) {
    coulomb_ = coulomb_ || f.friction.kind == FrictionLaw::Kind::Coulomb;
    smoothing_.include(f.friction);
  }
}

std::string RegularizedRows::node_text(std::size_t i) const {
  return "node " + std::to_string((*rows_)[i].kin.nodes[0]);
}

void RegularizedRows::begin_step(const StepView& v, const std::vector<ContactRow>& rows,
                                 std::vector<std::string>& events) {
  rows_ = &rows;
  const auto& ifaces = disc_.interfaces();
  // The state of rows that no longer exist (a slave off its master's
  // surface, the old slave after a role switch) is dropped.
  std::map<std::pair<int, Index>, char> next;
  active_.assign(rows.size(), 0);
  changed_.assign(rows.size(), 0);
  merit_bound_.assign(rows.size(), -1.0);
  res_.assign(rows.size(), {});
  results_.assign(rows.size(), {});
  lambda_.assign(rows.size(), 0.0);  // the augmented Lagrangian sets its own after this
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ContactRow& r = rows[i];
    const auto it = state_.find({r.iface, r.key});
    char on = it != state_.end() && it->second;
    if (!on && r.kin.gap0 <= s_.touch_tol) {
      on = 1;
      events.push_back("touch " + node_text(i) + " on " + ifaces[r.iface].name);
    }
    active_[i] = on;
    next[{r.iface, r.key}] = on;
  }
  for (const auto& [key, on] : state_)
    if (on && !next.count(key) && ifaces[key.first].die < 0)
      events.push_back("node " + std::to_string(key.second) + " leaves the master surface of " + ifaces[key.first].name);
  state_ = std::move(next);
  set_laws(v);
}

void RegularizedRows::set_laws(const StepView& v) {
  const auto& rows = *rows_;
  const auto& ifaces = disc_.interfaces();
  std::vector<RowArea> area;
  disc_.areas(v, rows, active_, area);
  laws_.assign(rows.size(), {});
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ContactRow& r = rows[i];
    const FrictionLaw& f = ifaces[r.iface].friction;
    RowLaw& l = laws_[i];
    // A solve's first rows after a remesh start from the factor of the old
    // row nearest them (ContactModel::take_over_rows).
    if (r.prior && s_.adapt.on) adaptive_.carry(r, r.prior->row_factor);
    l.beta = s_.beta_hat[r.iface] * r.weight * adaptive_.factor(r);
    l.inv_dt = s_.gap_correction && v.dt > 0 ? 1.0 / v.dt : 0.0;
    l.one_sided = one_sided();
    l.kind = f.kind;
    l.m = f.m;
    l.mu = f.mu;
    l.a = f.smoothing_speed(s_.speed_scale);
    l.k_weight = area[i].kw;
  }
}

void RegularizedRows::begin_attempts() { adaptive_.begin_step(); }

PenaltyRaise RegularizedRows::raise_penalty() {
  if (!rows_) return {};
  return adaptive_.raise(*rows_);
}

RowTerm RegularizedRows::evaluate(std::size_t i, const std::vector<Vec2>& vel) const {
  const ContactRow& r = (*rows_)[i];
  RowLaw law = laws_[i];
  law.a *= smoothing_.factor();
  law.merit_bound = merit_bound_[i];
  law.lambda = one_sided() ? lambda_[i] : 0.0;
  // The friction factor acts on rows in contact (Coulomb's bound follows
  // the normal force by itself).
  if (law.kind == FrictionLaw::Kind::Factor && !active_[i]) law.kind = FrictionLaw::Kind::None;
  // A row in contact keeps its normal stiffness in the Newton matrix when
  // an iterate lifts it off (a body held only by contacts would float).
  law.keep_stiffness = active_[i];
  return row_term(r.kin, law, vel);
}

double RegularizedRows::end_gap_rate(std::size_t i, const std::vector<Vec2>& vel) const {
  return gap_rate((*rows_)[i].kin, vel) + (*rows_)[i].kin.gap_from * laws_[i].inv_dt;
}

void RegularizedRows::add_terms(const std::vector<Vec2>& vel, TermSink& sink) const {
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    if (!engaged(i)) continue;
    add_row_term(sink, (*rows_)[i].kin, evaluate(i, vel));
  }
}

void RegularizedRows::anchor_merit(const std::vector<Vec2>& vel) {
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    merit_bound_[i] = -1;
    if (engaged(i)) merit_bound_[i] = evaluate(i, vel).bound;
  }
}

void RegularizedRows::settle(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out) {
  if (one_sided()) settle_one_sided(v, vel, out);
  else settle_two_sided(v, vel, out);
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    state_[{(*rows_)[i].iface, (*rows_)[i].key}] = active_[i];
    RowResult& r = results_[i];
    r = {};
    r.in_contact = active_[i];
    if (!engaged(i)) continue;
    r.normal = res_[i].normal_force;
    r.friction = res_[i].friction;
    r.slip = res_[i].gamma_t;
  }
  // Continuation in the friction smoothing at the run's first solve.
  if (smoothing_.relax()) out.resolve = true;
}

void RegularizedRows::settle_one_sided(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out) {
  const auto& ifaces = disc_.interfaces();
  bool changed = false;
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    res_[i] = (*rows_)[i].free ? RowTerm{} : evaluate(i, vel);
    const bool pressing = res_[i].normal_force > 0;
    if (pressing != static_cast<bool>(active_[i]) && !changed_[i]) {
      active_[i] = pressing;
      changed_[i] = 1;
      changed = changed || laws_[i].kind != FrictionLaw::Kind::None;
      out.events.push_back((pressing ? "touch " : "release ") + node_text(i) + (pressing ? " on " : " from ") +
                           ifaces[(*rows_)[i].iface].name);
      if (changed) res_[i] = evaluate(i, vel);
    }
  }
  if (changed) {
    set_laws(v);
    out.resolve = true;
  }
}

void RegularizedRows::settle_two_sided(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out) {
  const auto& ifaces = disc_.interfaces();
  double scale = 0;
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    res_[i] = active_[i] ? evaluate(i, vel) : RowTerm{};
    scale = std::max(scale, std::abs(res_[i].normal_force));
  }
  bool changed = false;
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    const ContactRow& r = (*rows_)[i];
    if (!active_[i]) continue;
    // The penalty pushes the slave out along +n: a negative normal force
    // pulls the bodies together.
    if (res_[i].normal_force < -s_.release_tol * scale) {
      active_[i] = 0;
      changed_[i] = 1;
      res_[i] = RowTerm{};
      changed = true;
      out.events.push_back("release " + node_text(i) + " from " + ifaces[r.iface].name);
    }
  }
  if (changed) {
    set_laws(v);
    out.resolve = true;
  }
}

}  // namespace rpfem
