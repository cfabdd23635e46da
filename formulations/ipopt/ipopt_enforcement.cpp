#include "ipopt/ipopt_enforcement.hpp"

#include "contact/friction_treatment.hpp"

#include <algorithm>
#include <cmath>

#include "contact/row_terms.hpp"

namespace rpfem {

namespace {

// Force scale of the objective: the softest body's yield stress over the
// slave surfaces (what the contact could carry; a point contact at the
// start carries far less, and its own load would put round-off above tol).
double force_scale(const Scene& scene, const ContactDiscretization& disc) {
  double sigma = INFINITY, area = 0;
  for (const auto& b : scene.bodies) sigma = std::min(sigma, b.law.yield(0.0));
  for (const auto& f : disc.interfaces()) area += f.area;
  return sigma * area;
}

}  // namespace

IpoptEnforcement::IpoptEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc)
    : disc_(disc), solver_(scene, settings, force_scale(scene, disc)) {
  require_friction_treatment(scene, name(), {true, true, false});
  for (const auto& f : disc.interfaces()) exact_any_ = exact_any_ || f.friction.exact(false);
  // The exact law is met to the bounds' fixed point (Coulomb's mu N from
  // the last pass): to 1e-10 where some law is exact, so that the law
  // holds to 1e-8 of each row's bound (kkt_friction); the arctan law's own
  // smoothing is larger than 1e-6.
  friction_tol_ = settings.real("friction_tolerance", exact_any_ ? 1e-10 : 1e-6, Range::positive(),
                                "relative change of the friction bounds that ends the fixed point");
  predict_ = settings.flag("predict_bounds", true);
  speed_scale_ = scene.largest_speed();
}

double IpoptEnforcement::smoothing_speed(std::size_t i) const {
  return disc_.interfaces()[(*rows_)[i].iface].friction.smoothing_speed(speed_scale_);
}

bool IpoptEnforcement::pressing(std::size_t i) const {
  if (bound_of_[i] < 0) return false;
  const BoundRow& b = bound_rows_[bound_of_[i]];
  return b.force > 0 && b.end_gap < kPressGap * b.h;
}

void IpoptEnforcement::begin_step(const StepView& v, const std::vector<ContactRow>& rows) {
  rows_ = &rows;
  bound_rows_.clear();
  bound_of_.assign(rows.size(), -1);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].free) continue;
    bound_of_[i] = static_cast<int>(bound_rows_.size());
    BoundRow b;
    b.kin = &rows[i].kin;
    b.h = rows[i].h;
    bound_rows_.push_back(b);
  }
  solver_.set_rows(&bound_rows_);
  results_.assign(rows.size(), {});
  solve_time_ = v.time;
  std::vector<double> force;
  predict_forces(rows, force);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (bound_of_[i] < 0) continue;
    const auto it = latest_force_.find({rows[i].iface, rows[i].key});
    bound_rows_[bound_of_[i]].start_force = it != latest_force_.end() ? it->second : 0.0;
    const auto f = latest_friction_.find({rows[i].iface, rows[i].key});
    bound_rows_[bound_of_[i]].start_friction = f != latest_friction_.end() ? f->second : 0.0;
  }
  flipped_.assign(rows.size(), 0);
  flips_ = 0;
  last_g_.clear();
  last_Fg_.clear();
  set_bounds(v, force);
  hand_bounds();
  solver_.first_loose(std::any_of(bound_.begin(), bound_.end(), [](double b) { return b > 0; }));
}

void IpoptEnforcement::hand_bounds() {
  for (std::size_t i = 0; i < rows_->size(); ++i)
    if (bound_of_[i] >= 0) bound_rows_[bound_of_[i]].exact_bound = exact(i) ? bound_[i] : 0.0;
}

void IpoptEnforcement::predict_forces(const std::vector<ContactRow>& rows, std::vector<double>& force) {
  // The first bounds of a solve: the pressing forces of the last settled
  // solves, extrapolated linearly in time to this solve's configuration,
  // through the last accepted step's (newer) and the one before it, or,
  // after this step's half-step solve, through that solve's and the last
  // accepted step's. Rows take their contact state from the newer record
  // (a row appears or leaves as the fixed point finds it). The bounds move
  // with the load, a few per cent a step in a press: from the newer record
  // alone the fixed point starts that far off; extrapolated, the error is
  // second order in dt, and the passes to friction_tolerance fall with it.
  const ForceRecord* older = &accepted_[0];
  const ForceRecord* newer = &accepted_[1];
  if (predict_ && in_step_.time > newer->time && in_step_.time < solve_time_) older = newer, newer = &in_step_;
  const double span = newer->time - older->time;
  const double ahead = solve_time_ - newer->time;
  // At most one span ahead: a step longer than the last (after cuts) is
  // extrapolated no further than the records' own spacing.
  const double ratio = predict_ && span > 0 && ahead > 0 ? std::min(ahead / span, 1.0) : 0.0;
  force.assign(rows.size(), 0.0);
  on_.assign(rows.size(), 0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::pair<int, Index> key{rows[i].iface, rows[i].key};
    const auto it = newer->force.find(key);
    if (it == newer->force.end()) continue;
    double f = it->second;
    const auto was = older->force.find(key);
    if (ratio > 0 && was != older->force.end()) f += ratio * (it->second - was->second);
    on_[i] = it->second > 0;
    force[i] = std::max(f, 0.0);
  }
}

void IpoptEnforcement::record_pressing(ForceRecord& into) const {
  into.time = solve_time_;
  into.force.clear();
  for (std::size_t i = 0; i < rows_->size(); ++i)
    if (pressing(i)) into.force[{(*rows_)[i].iface, (*rows_)[i].key}] = bound_rows_[bound_of_[i]].force;
}

void IpoptEnforcement::set_bounds(const StepView& v, const std::vector<double>& force) {
  const auto& rows = *rows_;
  std::vector<RowArea> area;
  disc_.areas(v, rows, on_, area);
  bound_.assign(rows.size(), 0.0);
  cap_.assign(rows.size(), 0.0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    bound_[i] = friction_bound(disc_.interfaces()[rows[i].iface].friction, on_[i], force[i], area[i].kw);
    cap_[i] = on_[i] ? area[i].kw : 0.0;
  }
}

void IpoptEnforcement::add_terms(const StepView&, const std::vector<Vec2>& vel, TermSink& sink) const {
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    if (!(bound_[i] > 0) || (*rows_)[i].free || exact(i)) continue;  // exact: the solver's slack rows
    const PairKinematics& k = (*rows_)[i].kin;
    RowLaw l;
    l.normal = false;
    l.fixed_bound = bound_[i];
    l.a = smoothing_speed(i);
    add_row_term(sink, k, row_term(k, l, vel));
  }
}

StepCheck IpoptEnforcement::settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) {
  // The friction force of this solve, then the fixed point on the bounds.
  StepCheck out;
  const auto& rows = *rows_;
  std::vector<double> force(rows.size(), 0.0), before = bound_;
  const int flips_before = flips_;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    RowResult& r = results_[i];
    r = {};
    if (bound_of_[i] < 0) continue;
    r.normal = bound_rows_[bound_of_[i]].force;
    r.in_contact = pressing(i);
    r.slip = slip_rate(rows[i].kin, vel);
    if (exact(i)) r.friction = bound_rows_[bound_of_[i]].friction;  // q - p of its slack rows
    else if (bound_[i] > 0) r.friction = -bound_[i] * arctan_potential(r.slip, smoothing_speed(i)).dpsi;
    if (r.in_contact != static_cast<bool>(on_[i]) && !flipped_[i]) on_[i] = r.in_contact, flipped_[i] = 1, ++flips_;
    if (on_[i]) force[i] = std::max(r.normal, 0.0);
  }
  set_bounds(v, force);
  if (exact_any_) classify(bound_);
  double largest = 0, change = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    largest = std::max({largest, before[i], bound_[i]});
    change = std::max(change, std::abs(bound_[i] - before[i]));
  }
  friction_change_ = largest > 0 ? change / largest : 0.0;
  out.resolve = friction_change_ > friction_tol_;
  if (out.resolve) accelerate(before, flips_before);
  // A pass to the loose tol while the bounds still move by more than
  // kLooseAbove friction tolerances (and kLooseAbove kLooseResolution: its
  // solution is only the next bounds' source), to warm_tol near the fixed
  // point; the solution taken is never a loose one (one more pass where
  // the last was loose).
  if (!out.resolve && solver_.last_loose()) out.resolve = true;
  if (out.resolve) {
    solver_.warm_next(friction_change_ > kLooseAbove * std::max(friction_tol_, kLooseResolution));
    hand_bounds();
    return out;
  }
  // Settled: its forces start the next solve (BoundRow::start_force), and
  // its pressing forces predict the next solve's bounds within this step.
  latest_force_.clear();
  latest_friction_.clear();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (bound_of_[i] < 0) continue;
    latest_force_[{rows[i].iface, rows[i].key}] = bound_rows_[bound_of_[i]].force;
    if (exact(i)) latest_friction_[{rows[i].iface, rows[i].key}] = bound_rows_[bound_of_[i]].friction;
  }
  record_pressing(in_step_);
  return out;
}

void IpoptEnforcement::classify(const std::vector<double>& g) {
  // A row in contact sticks where its slip rate is nearer zero than its
  // friction force is to the bound, in their scales,
  //   |gamma_T| / v_ref < 1 - |T| / g,
  // and slips elsewhere: the exact solution (a polished one,
  // ipopt_step_solver.hpp) has one of the two zero, an interior point's
  // both small, their product Ipopt's complementarity. Measured against
  // the bound of the solve's own forces (Coulomb's mu N of this solve, not
  // of the last), as SsnEnforcement::measure.
  kkt_friction_ = kkt_stick_slip_ = 0;
  stick_ = slip_ = 0;
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    RowResult& r = results_[i];
    if (bound_of_[i] < 0 || !exact(i) || !r.in_contact) continue;
    // A zero bound (a contact area of zero: a point contact), or held
    // frictionless (one direction, ipopt_step_solver.hpp): its force is its
    // bound, zero; slipping, as under ssn.
    if (!(g[i] > 0) || !bound_rows_[bound_of_[i]].friction_rows) {
      r.stick = -1, ++slip_;
      continue;
    }
    const double T = r.friction, rate = std::abs(r.slip) / speed_scale_;
    kkt_friction_ = std::max(kkt_friction_, std::max(0.0, std::abs(T) - g[i]) / g[i]);
    if (rate < 1 - std::abs(T) / g[i]) {
      r.stick = 1, ++stick_;
      kkt_stick_slip_ = std::max(kkt_stick_slip_, rate);
    } else {
      r.stick = -1, ++slip_;
      const double sign = r.slip > 0 ? 1.0 : r.slip < 0 ? -1.0 : 0.0;
      if (sign != 0) kkt_friction_ = std::max(kkt_friction_, std::abs(T + g[i] * sign) / g[i]);
    }
  }
}

void IpoptEnforcement::accelerate(const std::vector<double>& g, int flips_before) {
  // bound_ holds F(g), the bounds from this solve's forces. With the last
  // pass's (g', F(g')) and the residuals r = F(g) - g, r' = F(g') - g':
  //   theta = r . (r - r') / |r - r'|^2,   g_next = F(g) - theta (F(g) - F(g'))
  // (Anderson mixing of depth one), each bound kept within [0, k w]. Plain
  // iteration where a row changed its contact state (the map jumped) or
  // the residual grew.
  const std::vector<double> Fg = bound_;
  const bool have_last = last_g_.size() == g.size() && flips_ == flips_before;
  std::vector<double> next = Fg;
  if (have_last) {
    double rr = 0, rd = 0, dd = 0, last_rr = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const double r = Fg[i] - g[i], r_last = last_Fg_[i] - last_g_[i], d = r - r_last;
      rr += r * r, last_rr += r_last * r_last, rd += r * d, dd += d * d;
    }
    if (dd > 0 && rr < last_rr) {
      const double theta = rd / dd;
      for (std::size_t i = 0; i < g.size(); ++i)
        next[i] = std::clamp(Fg[i] - theta * (Fg[i] - last_Fg_[i]), 0.0, cap_[i]);
    }
  }
  last_g_ = g;
  last_Fg_ = Fg;
  bound_ = next;
}

void IpoptEnforcement::end_step(const StepView&, const std::vector<Vec2>&) {
  // The next steps' first bounds come from this step's forces (its last
  // solve's: the end of the step).
  accepted_[0] = std::move(accepted_[1]);
  record_pressing(accepted_[1]);
  in_step_ = ForceRecord{};
}

void IpoptEnforcement::columns(std::vector<NamedValue>& out) const {
  const Kkt& k = solver_.kkt();
  out.push_back({"kkt_primal", k.primal});
  out.push_back({"kkt_dual", k.dual});
  out.push_back({"kkt_complementarity", k.complementarity});
  out.push_back({"kkt_stationarity", k.stationarity});
  out.push_back({"kkt_round_off", k.round_off});
  out.push_back({"friction_change", friction_change_});
  out.push_back({"warm_fallbacks", static_cast<double>(solver_.warm_failures())});
  const MumpsAnalysisCounts a = solver_.mumps_analyses();
  out.push_back({"mumps_analyses", static_cast<double>(a.analysed)});
  out.push_back({"mumps_analyses_reused", static_cast<double>(a.reused)});
  if (!exact_any_) return;
  out.push_back({"stick_rows", static_cast<double>(stick_)});
  out.push_back({"slip_rows", static_cast<double>(slip_)});
  out.push_back({"kkt_friction", kkt_friction_});
  out.push_back({"kkt_stick_slip", kkt_stick_slip_});
  out.push_back({"polished", solver_.polished() ? 1.0 : 0.0});
}

void IpoptEnforcement::derived(std::vector<NamedValue>& out) const {
  solver_.derived(out);
  for (const auto& f : disc_.interfaces()) out.push_back({"ipopt." + f.name + ".element_size_mm", f.h});
}

}  // namespace rpfem
