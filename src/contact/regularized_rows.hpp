// Rows enforced by terms in the step's functional (contact/row_terms.hpp):
// the penalty (lambda = 0) and the augmented Lagrangian (lambda from
// Uzawa's updates, set by its enforcement) share this. Per row:
//   beta = beta_hat w_s, w_s the slave node's lumped contact area
//   (ContactRow::weight), beta_hat per interface (the enforcement's).
// Contact state (per row identity, carried across configurations): a
// slave touching (gap <= touch tolerance) becomes in contact.
//   One-sided (the default, with the gap correction): every row that is
//   not free carries its term; the state only reports the rows that press
//   (N > 0), switches the friction factor on and off and sets the contact
//   area of the sticking bound k w (which caps Coulomb's mu N too). A state
//   change matters only to friction, so only then is the step solved
//   again; a row changes state at most once per solve (no flip-flop).
//   Two-sided (gap_correction = false, paper eq. 7 exactly): only rows in
//   contact carry a term; one whose normal force turns tensile is released
//   and the step solved again.
// Friction: the live bound with its consistent tangent (Coulomb: UMFPACK,
// and a merit anchored per iterate for the line search); the smoothing
// speed by continuation at the run's first solve.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "contact/adaptive_penalty.hpp"
#include "contact/discretization.hpp"
#include "contact/enforcement.hpp"
#include "contact/row_terms.hpp"
#include "contact/saved_members.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

struct Scene;

struct RegularizedSettings {
  std::vector<double> beta_hat;  // MPa s/mm, per interface
  bool gap_correction = true;
  double touch_tol = 0;          // mm
  double release_tol = 0;        // relative to the largest contact force
  double speed_scale = 0;        // mm/s: a = a_relative * speed_scale
  PenaltyAdaptation adapt;       // off: every row's beta is beta_hat w
};

// The default beta_hat of each interface (MPa s/mm): `factor` times
// 1e4 sigma_ref L / (v_ref h) (formulations/penalty), or `beta` if given.
// Throws InputError when nothing moves (no speed scale).
std::vector<double> default_beta_hat(const Scene& scene, const ContactDiscretization& disc, double factor,
                                     std::optional<double> beta);

class RegularizedRows {
 public:
  RegularizedRows(const ContactDiscretization& disc, RegularizedSettings s);

  void begin_step(const StepView& v, const std::vector<ContactRow>& rows, std::vector<std::string>& events);
  void add_terms(const std::vector<Vec2>& vel, TermSink& sink) const;
  TangentKind tangent() const { return {!coulomb_, !coulomb_, coulomb_}; }
  void anchor_merit(const std::vector<Vec2>& vel);
  // The contact state after a converged solve (and the results);
  // out.resolve when it changed what the terms are.
  void settle(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out);
  const std::vector<RowResult>& results() const { return results_; }
  // The multiplier of each row (N): 0 for the penalty.
  std::vector<double>& lambda() { return lambda_; }
  const std::vector<ContactRow>& rows() const { return *rows_; }
  // The end-of-step gap rate r = gamma_N + g_from / dt of row i (mm/s).
  double end_gap_rate(std::size_t i, const std::vector<Vec2>& vel) const;
  bool engaged(std::size_t i) const { return one_sided() ? !(*rows_)[i].free : bool(active_[i]); }
  double beta(std::size_t i) const { return laws_[i].beta; }
  const RegularizedSettings& settings() const { return s_; }
  // Its state, for ContactEnforcement::save_state.
  std::any save_state() const {
    return save_members(rows_, state_, active_, changed_, laws_, lambda_, merit_bound_, res_, results_, smoothing_);
  }
  void restore_state(const std::any& saved) {
    restore_members(saved, rows_, state_, active_, changed_, laws_, lambda_, merit_bound_, res_, results_, smoothing_);
  }
  // The adaptive penalty (contact/adaptive_penalty.hpp): a step's count of
  // raises begun; after an attempt, the rows too deep raised (rows() at
  // the end configuration). The re-solve's contact state is the step's
  // start, restored by the stepper (save_state).
  void begin_attempts();
  PenaltyRaise raise_penalty();
  const AdaptivePenalty& adaptive() const { return adaptive_; }
  // Row i's factor on its beta (1 before any rows).
  double factor(std::size_t i) const { return rows_ && i < rows_->size() ? adaptive_.factor((*rows_)[i]) : 1.0; }

 private:
  bool one_sided() const { return s_.gap_correction; }
  void set_laws(const StepView& v);
  RowTerm evaluate(std::size_t i, const std::vector<Vec2>& vel) const;
  void settle_one_sided(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out);
  void settle_two_sided(const StepView& v, const std::vector<Vec2>& vel, StepCheck& out);
  std::string node_text(std::size_t i) const;

  const ContactDiscretization& disc_;
  RegularizedSettings s_;
  const std::vector<ContactRow>* rows_ = nullptr;
  std::map<std::pair<int, Index>, char> state_;  // in contact, by row identity
  AdaptivePenalty adaptive_;
  std::vector<char> active_, changed_;
  std::vector<RowLaw> laws_;
  std::vector<double> lambda_, merit_bound_;
  std::vector<RowTerm> res_;  // at the last converged solve
  std::vector<RowResult> results_;
  SmoothingContinuation smoothing_;
  bool coulomb_ = false;
};

// The enforcements whose rows are terms (penalty, augmented Lagrangian):
// the hooks the rows answer, shared; each adds its settle() and its
// records.
class RegularizedEnforcement : public ContactEnforcement {
 public:
  RegularizedEnforcement(const ContactDiscretization& disc, RegularizedSettings s) : disc_(disc), rows_(disc, std::move(s)) {}
  void begin_step(const StepView& v, const std::vector<ContactRow>& rows) override { rows_.begin_step(v, rows, events_); }
  void add_terms(const StepView&, const std::vector<Vec2>& vel, TermSink& sink) const override {
    rows_.add_terms(vel, sink);
  }
  TangentKind tangent() const override { return rows_.tangent(); }
  void remember_start() override { rows_.begin_attempts(); }
  std::optional<std::string> retune() override;
  double kept_depth() const override {
    const auto& a = rows_.settings().adapt;
    return a.on ? a.tolerance : 0.0;
  }
  double row_factor(std::size_t i) const override { return rows_.factor(i); }
  void anchor_merit(const StepView&, const std::vector<Vec2>& vel) override { rows_.anchor_merit(vel); }
  const std::vector<RowResult>& results() const override { return rows_.results(); }
  std::any save_state() const override { return save_members(rows_.save_state(), events_); }
  void restore_state(const std::any& saved) override {
    std::any rows;
    restore_members(saved, rows, events_);
    rows_.restore_state(rows);
  }

 protected:
  // The contact state after a converged solve, with the events of the
  // rows' search: what every settle() starts with.
  StepCheck settle_state(const StepView& v, const std::vector<Vec2>& vel) {
    StepCheck out;
    out.events.swap(events_);
    rows_.settle(v, vel, out);
    return out;
  }
  // beta per interface and the element size, as "<name>.<interface>.*";
  // the adaptive penalty's settings.
  void derived_betas(const std::string& name, std::vector<NamedValue>& out) const;
  // With the adaptive penalty: its columns, penalty_factor (the largest
  // factor on a row's beta in force) and penalty_raises (the step's
  // re-solves).
  void adaptive_columns(std::vector<NamedValue>& out) const;

  const ContactDiscretization& disc_;
  RegularizedRows rows_;
  std::vector<std::string> events_;
};

}  // namespace rpfem
