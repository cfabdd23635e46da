#include "ssn/ssn_enforcement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "contact/friction_treatment.hpp"

namespace rpfem {

namespace {

// A slip rate below this fraction of the speed scale is zero (the
// friction conditions' tolerance on a sticking row's slip).
constexpr double kZeroSlip = 1e-8;

SsnSettings read_settings(const Scene& scene, CaseSection& s) {
  SsnSettings out;
  out.newton = scene.solver.newton;
  out.lu = scene.solver.lu;
  out.speed_scale = scene.largest_speed();
  out.condense = s.flag("condense", true);
  out.augmented = s.flag("augmented", true);
  out.c_normal = s.real("c_normal", 1.0, Range::positive(), "times sigma_ref w / v_ref: the normal function's c_N");
  out.c_tangential = s.real("c_tangential", 0.1, Range::positive(), "times sigma_ref w / v_ref: the friction function's c_T");
  return out;
}

}  // namespace

SsnEnforcement::SsnEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc)
    : disc_(disc), solver_(read_settings(scene, settings)) {
  require_friction_treatment(scene, name(), {false, true, true});
  if (disc.overconstrains())
    throw InputError(scene.file + ": contact.discretization = '" + disc.name() + "': enforcement 'ssn' solves each row's forces as "
                     "unknowns and needs linearly independent rows; between bodies this discretization holds each contact "
                     "from both sides; expected node_to_segment or mortar");
}

void SsnEnforcement::begin_step(const StepView& v, const std::vector<ContactRow>& rows) {
  rows_ = &rows;
  state_.assign(rows.size(), {});
  bool prior = false;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto it = latest_.find({rows[i].iface, rows[i].key});
    if (it != latest_.end()) {
      state_[i] = it->second;
    } else if (const auto& p = rows[i].prior; p && p->normal > 0) {
      // After a remesh: the forces the old mesh carried there.
      SsnRowState& st = state_[i];
      st.active = true, st.stick = p->stick;
      st.lambda_n = p->normal, st.lambda_t = p->friction;
      prior = true;
    }
  }
  if (prior) solver_.hold_starting_sets();
  // c_j (ssn_enforcement.hpp); a row of no area (on the axis) takes a
  // hundredth of its interface's mean.
  const auto& ifaces = disc_.interfaces();
  std::vector<double> mean(ifaces.size(), 0.0);
  std::vector<int> count(ifaces.size(), 0);
  for (const ContactRow& r : rows) mean[r.iface] += r.weight, ++count[r.iface];
  for (std::size_t f = 0; f < ifaces.size(); ++f) mean[f] = count[f] ? mean[f] / count[f] : 0.0;
  c_.resize(2 * rows.size());
  const SsnSettings& s = solver_.settings();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double w = std::max(rows[i].weight, 1e-2 * mean[rows[i].iface]);
    const double c = ifaces[rows[i].iface].sigma_ref * w / speed_scale();
    c_[2 * i] = s.c_normal * c, c_[2 * i + 1] = s.c_tangential * c;
  }
  solver_.set_rows(&rows, &c_, &state_, [this](const StepView& sv, const std::vector<char>& active,
                                          std::vector<RowFriction>& out) { frictions(sv, active, out); });
}

void SsnEnforcement::frictions(const StepView& v, const std::vector<char>& active, std::vector<RowFriction>& out) const {
  std::vector<RowArea> area;
  disc_.areas(v, *rows_, active, area);
  const auto& ifaces = disc_.interfaces();
  out.assign(rows_->size(), {});
  for (std::size_t i = 0; i < rows_->size(); ++i) {
    const FrictionLaw& law = ifaces[(*rows_)[i].iface].friction;
    RowFriction& f = out[i];
    if (law.kind == FrictionLaw::Kind::Factor) f.kind = RowFriction::Kind::Tresca, f.bound = law.m * area[i].kw;
    else if (law.kind == FrictionLaw::Kind::Coulomb) f.kind = RowFriction::Kind::Coulomb, f.mu = law.mu, f.cap = area[i].kw;
  }
}

StepCheck SsnEnforcement::settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) {
  StepCheck out;
  const auto& rows = *rows_;
  const auto& ifaces = disc_.interfaces();
  results_.assign(rows.size(), {});
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SsnRowState& s = state_[i];
    RowResult& r = results_[i];
    r.in_contact = s.active;
    r.normal = s.lambda_n;
    r.friction = s.lambda_t;
    r.slip = slip_rate(rows[i].kin, vel);
    if (s.active && ifaces[rows[i].iface].friction.kind != FrictionLaw::Kind::None) r.stick = s.stick ? 1 : -1;
    const auto key = std::make_pair(rows[i].iface, rows[i].key);
    const auto it = latest_.find(key);
    const bool was = it != latest_.end() && it->second.active;
    if (s.active != was)
      out.events.push_back(std::string(s.active ? "touch" : "release") + " node " + std::to_string(rows[i].kin.nodes[0]) +
                           " on " + ifaces[rows[i].iface].name);
    latest_[key] = s;
  }
  measure(v);
  return out;
}

namespace {

std::string format(const char* fmt, double a, double b = 0) {
  std::string out(static_cast<std::size_t>(std::snprintf(nullptr, 0, fmt, a, b)), '\0');
  std::snprintf(out.data(), out.size() + 1, fmt, a, b);
  return out;
}

}  // namespace

void SsnEnforcement::measure(const StepView& v) {
  const auto& rows = *rows_;
  // The largest over the step's solves (the midpoint scheme's half step
  // and its end).
  if (v.step != measured_step_) {
    primal_ = complementarity_ = friction_ = stick_slip_ = 0, measured_step_ = v.step;
    step_stats_ = {};
    cause_.clear();
  }
  const SsnSolveStats& solve = solver_.stats();
  step_stats_.iterations += solve.iterations;
  step_stats_.set_changes += solve.set_changes;
  step_stats_.condensed += solve.condensed;
  step_stats_.augmented += solve.augmented;
  stick_ = slip_ = 0;
  double total = 0;
  for (const SsnRowState& s : state_) total += std::max(s.lambda_n, 0.0);
  // A row's violation above the step's largest so far names the row, its
  // words formatted only then (friction_violation_cause()).
  const auto violates = [&](double by, std::size_t i, double& worst, const char* why, double a, double b = 0) {
    if (by > std::max(friction_, stick_slip_)) cause_ = "node " + std::to_string(rows[i].kin.nodes[0]) + " " + format(why, a, b);
    worst = std::max(worst, by);
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SsnRowState& s = state_[i];
    if (rows[i].free) continue;
    const double gap = s.end_gap_rate * v.dt;
    primal_ = std::max(primal_, std::max(0.0, -gap) / rows[i].h);
    if (total > 0) complementarity_ = std::max(complementarity_, std::abs(s.lambda_n * s.end_gap_rate) / (total * speed_scale()));
    if (!s.active || results_[i].stick == 0) continue;
    const double g = std::max(s.bound, 1e-300);
    const double ratio = std::abs(s.lambda_t) / g;
    if (s.grazing) {
      // On the friction factor's jump: any force within the bound that
      // does not drive the slip (ncp.hpp). A row left there after its
      // rounds (ssn_step_solver.cpp) has no solution on any branch.
      ++slip_;
      const bool along = s.lambda_t * s.slip_rate > 0;
      const std::string why = std::string("held grazing (no normal force, slip rate %.3g mm/s) with a friction force "
                                          "%.3g times its bound") +
                              (along ? " along its slip" : "") +
                              ": on the friction factor's jump, where pressing at its bound lifts it off and free it "
                              "penetrates";
      violates(along ? ratio : std::max(0.0, ratio - 1), i, friction_, why.c_str(), s.slip_rate, ratio);
      continue;
    }
    if (s.stick) {
      ++stick_;
      const double slip = std::abs(s.slip_rate) / speed_scale();
      violates(ratio - 1, i, friction_, "sticking with a friction force %.3g times its bound", ratio);
      violates(slip, i, stick_slip_, "sticking while it slips at %.3g of the speed scale", slip);
    } else {
      ++slip_;
      violates(ratio - 1, i, friction_, "slipping with a friction force %.3g times its bound", ratio);
      // A slipping row whose slip rate is at round-off (the neutral point
      // reached: the solution at the kink between the sets) meets the law
      // as a sticking row, its force at the bound in either direction.
      if (std::abs(s.slip_rate) <= kZeroSlip * speed_scale()) continue;
      const double sign = s.slip_rate > 0 ? 1.0 : -1.0;
      const double off = std::abs(s.lambda_t + s.bound * sign) / g;
      violates(off, i, friction_, "slipping at %.3g mm/s with a friction force %.3g of its bound off the bound opposing it",
               s.slip_rate, off);
    }
  }
}

void SsnEnforcement::columns(std::vector<NamedValue>& out) const {
  const SsnSolveStats& s = step_stats_;
  out.push_back({"ssn_iterations", double(s.iterations)});
  out.push_back({"ssn_set_changes", double(s.set_changes)});
  out.push_back({"ssn_condensed", double(s.condensed)});
  out.push_back({"ssn_augmented", double(s.augmented)});
  out.push_back({"stick_rows", double(stick_)});
  out.push_back({"slip_rows", double(slip_)});
  out.push_back({"kkt_primal", primal_});
  out.push_back({"kkt_complementarity", complementarity_});
  out.push_back({"kkt_friction", friction_});
  out.push_back({"kkt_stick_slip", stick_slip_});
}

void SsnEnforcement::derived(std::vector<NamedValue>& out) const {
  const SsnSettings& s = solver_.settings();
  out.push_back({"ssn.c_normal", s.c_normal});
  out.push_back({"ssn.c_tangential", s.c_tangential});
  out.push_back({"ssn.condense", s.condense ? 1.0 : 0.0});
  out.push_back({"ssn.augmented", s.augmented ? 1.0 : 0.0});
  out.push_back({"ssn.speed_scale_mm_s", speed_scale()});
}

}  // namespace rpfem
