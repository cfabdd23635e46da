// "ipopt": the rows as the inequality constraints of each step's
// constrained minimization (ipopt_step_solver.hpp), the active set Ipopt's
// business. Friction, by the arctan law (the default): its potential
// B psi(gamma_T) (contact/row_terms.hpp) with its bound fixed in a solve,
// so the objective stays a potential with a symmetric Hessian and Ipopt
// solves a convex problem. Exact (`regularization = "exact"`): the
// dissipation B |gamma_T| with the bound fixed in a solve, made smooth by a
// slack per row (ipopt_step_solver.hpp), the friction force the difference
// of its two rows' multipliers; each row in contact reported sticking or
// slipping (RowResult::stick). Either way the bound follows the
// multipliers by a fixed point over the
// solves of a step until it changes by less than `friction_tolerance` of
// the largest bound (each pass's bounds Anderson-mixed with the last
// pass's, accelerate(); the passes re-solve the same program, warm-started
// from the last multipliers, ipopt_step_solver.hpp):
//   friction factor: B = m k w on the rows pressing in the last solve
//   Coulomb:         B = min(mu N, k w), N the last solve's multiplier
// (k w: the sticking bound of the rows' contact areas, as everywhere).
#pragma once
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "contact/enforcement.hpp"
#include "contact/saved_members.hpp"
#include "io/case_file.hpp"
#include "ipopt/ipopt_step_solver.hpp"
#include "model/scene.hpp"

namespace rpfem {

class IpoptEnforcement final : public ContactEnforcement {
 public:
  IpoptEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc);
  std::string name() const override { return "ipopt"; }
  void begin_step(const StepView& v, const std::vector<ContactRow>& rows) override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override;
  StepSolver* solver() override { return &solver_; }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  const std::vector<RowResult>& results() const override { return results_; }
  void end_step(const StepView& v, const std::vector<Vec2>& vel) override;
  void columns(std::vector<NamedValue>& out) const override;
  std::optional<double> penetration_rel() const override { return solver_.kkt().primal; }
  void derived(std::vector<NamedValue>& out) const override;
  std::optional<double> friction_violation() const override {
    return exact_any_ ? std::optional<double>(std::max(kkt_friction_, kkt_stick_slip_)) : std::nullopt;
  }
  // The contact state (the solver's own warm start is a solve's: each
  // solve's first pass starts from the rows' forces, BoundRow::start_force).
  std::any save_state() const override {
    return save_members(rows_, bound_rows_, bound_of_, bound_, cap_, last_g_, last_Fg_, flips_, on_, flipped_, results_,
                        latest_force_, latest_friction_, accepted_[0], accepted_[1], in_step_, solve_time_,
                        friction_change_, kkt_friction_, kkt_stick_slip_, stick_, slip_);
  }
  void restore_state(const std::any& saved) override {
    restore_members(saved, rows_, bound_rows_, bound_of_, bound_, cap_, last_g_, last_Fg_, flips_, on_, flipped_,
                    results_, latest_force_, latest_friction_, accepted_[0], accepted_[1], in_step_, solve_time_,
                    friction_change_, kkt_friction_, kkt_stick_slip_, stick_, slip_);
  }

 private:
  // The pressing forces (N) of a settled solve, and the time of its
  // configuration (s; NaN: none).
  struct ForceRecord {
    double time = NAN;
    std::map<std::pair<int, Index>, double> force;
  };
  // In contact after the last solve: at zero end gap (to kPressGap of the
  // element size) with a compressive force. An interior point leaves tiny
  // positive multipliers (about mu / slack) on rows far from contact; they
  // must not count as contact (a ring's free faces got die friction).
  bool pressing(std::size_t i) const;
  static constexpr double kPressGap = 1e-6;
  // Friction passes whose bounds change by more than this many friction
  // tolerances are solved to Ipopt's loose tol only (ipopt_step_solver.hpp),
  // and no pass whose bounds change by kLooseAbove kLooseResolution or
  // less: a loose pass starts from the last pass's multipliers and stops
  // where its start meets loose_tol, so it follows the bounds to about
  // that resolution only. Measured: under exact Coulomb friction (upsetting
  // mu = 0.5) the loose passes' own fixed point lay 4e-5 from the tight
  // passes', and at friction_tolerance = 1e-10 the passes cycled between
  // the two.
  static constexpr double kLooseAbove = 100;
  static constexpr double kLooseResolution = 1e-6;
  // k w and the friction bound of every row from which rows are in contact
  // (on_) and the rows' normal forces.
  void set_bounds(const StepView& v, const std::vector<double>& force);
  double smoothing_speed(std::size_t i) const;
  // Whether row i's friction law is treated exactly (the slack rows).
  bool exact(std::size_t i) const { return disc_.interfaces()[(*rows_)[i].iface].friction.exact(false); }
  // The bounds of the exact rows into the solver's rows (BoundRow::exact_bound).
  void hand_bounds();
  // Exact friction after a solve (results_ set, `g` the bounds of its
  // forces): each row in contact sticking or slipping, and the friction
  // law's residuals (kkt_friction_, kkt_stick_slip_).
  void classify(const std::vector<double>& g);
  // A solve's first normal forces (and on_) from the settled solves before it.
  void predict_forces(const std::vector<ContactRow>& rows, std::vector<double>& force);
  void record_pressing(ForceRecord& into) const;
  // The next pass's bounds from this pass's (`g`, bound_ = F(g)).
  void accelerate(const std::vector<double>& g, int flips_before);

  const ContactDiscretization& disc_;
  IpoptStepSolver solver_;
  const std::vector<ContactRow>* rows_ = nullptr;
  std::vector<BoundRow> bound_rows_;
  std::vector<int> bound_of_;  // per row: its BoundRow, -1 for a free row
  std::vector<double> bound_;  // N, per row
  std::vector<double> cap_;    // N, per row: the sticking bound k w
  // Anderson mixing of depth one on the fixed point g -> F(g) of the bounds
  // (Walker and Ni 2011, eq. 1.2 with m = 1): the last pass's bounds and
  // their image, empty at a step's first pass.
  std::vector<double> last_g_, last_Fg_;
  int flips_ = 0;  // rows whose contact state changed in this step
  // Per row: in contact for the friction bounds, and whether that changed
  // in this step already. A row's state changes at most once a step, as
  // the penalty's: a node whose friction factor lifts it off the die and
  // whose release lets it press again otherwise alternates until the
  // step's passes run out (the backward extrusion at 3.5 mm, "contact
  // state did not settle in 50 passes" at every halving).
  std::vector<char> on_, flipped_;
  std::vector<RowResult> results_;
  std::map<std::pair<int, Index>, double> latest_force_;  // N: every row's force in the latest settled solve
  std::map<std::pair<int, Index>, double> latest_friction_;  // N: every exact row's friction force there
  ForceRecord accepted_[2];  // the last two accepted steps' (older first)
  ForceRecord in_step_;      // this step's latest settled solve (the half step's)
  double solve_time_ = 0;    // s: the configuration of the solve under way
  double speed_scale_ = 0, friction_tol_ = 0, friction_change_ = 0;
  bool predict_ = true;  // predict_bounds: extrapolate (else the last step's end forces)
  bool exact_any_ = false;  // some interface's friction is exact
  // Exact friction, of the last solve: the law's largest violation over
  // the bound (|T| above g; a slipping row's |T + g sign gamma_T|), a
  // sticking row's largest slip rate over the speed scale, and the rows
  // sticking and slipping (as SsnEnforcement's columns).
  double kkt_friction_ = 0, kkt_stick_slip_ = 0;
  int stick_ = 0, slip_ = 0;
};

}  // namespace rpfem
