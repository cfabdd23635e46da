// "ssn": exact contact and friction by a semi-smooth Newton method (primal-
// dual active set) on the rows' complementarity functions (ncp.hpp), each
// step's velocities and row forces solved together by its own step solver
// (ssn_step_solver.hpp). No penalty, no smoothing speed: the end-of-step
// gap of a row in contact is zero, a sticking row's slip rate is zero and a
// slipping row's friction force is its bound, opposing the slip, to the
// Newton tolerance; the friction law's `regularization` is "exact" (the
// default here; "arctan" is refused). The contact state is the solution's:
// a row is in contact where its normal condition is active, and the state
// never asks for another solve. Each row's forces start from the latest
// converged solve's of the same row identity (iface, key).
// Friction bounds (per iterate, from the active set's contact areas, as
// every enforcement's: contact_row.hpp's RowArea):
//   friction factor: g = m k w;  Coulomb: g = min(mu lambda_N, k w).
// The functions' parameters c_N,j = c_normal c_j and c_T,j = c_tangential
// c_j with c_j = sigma_ref w_j / v_ref (N s/mm):
// the force per slip rate of the row's share of the surface (w_j, its
// lumped area) flowing at the softer side's initial flow stress when it
// slips at the scene's largest speed v_ref. It sets how the sets are
// guessed from an iterate, not the solution; K's diagonal, the other
// choice, is dominated by the volumetric penalty (alpha = 1e5 sigma /
// rate) and made a sticking row's slip 1e5 times too decisive: the ring at
// m = 1 never found its sticking zone.
// Rows against dies and between bodies, of any discretization whose rows
// are independent (node to segment one pass, mortar; two pass sets two
// rows on one contact and its system is singular).
#pragma once
#include <map>
#include <utility>
#include <vector>

#include "contact/enforcement.hpp"
#include "contact/saved_members.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"
#include "ssn/ssn_step_solver.hpp"

namespace rpfem {

class SsnEnforcement final : public ContactEnforcement {
 public:
  SsnEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc);
  std::string name() const override { return "ssn"; }
  void begin_step(const StepView& v, const std::vector<ContactRow>& rows) override;
  void add_terms(const StepView&, const std::vector<Vec2>&, TermSink&) const override {}
  StepSolver* solver() override { return &solver_; }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  const std::vector<RowResult>& results() const override { return results_; }
  void columns(std::vector<NamedValue>& out) const override;
  std::optional<double> penetration_rel() const override { return primal_; }
  std::optional<double> friction_violation() const override { return std::max(friction_, stick_slip_); }
  std::string friction_violation_cause() const override { return cause_; }
  void derived(std::vector<NamedValue>& out) const override;
  std::any save_state() const override {
    return save_members(rows_, state_, c_, results_, latest_, primal_, complementarity_, friction_, stick_slip_,
                        measured_step_, stick_, slip_, step_stats_, cause_);
  }
  void restore_state(const std::any& saved) override {
    restore_members(saved, rows_, state_, c_, results_, latest_, primal_, complementarity_, friction_, stick_slip_,
                    measured_step_, stick_, slip_, step_stats_, cause_);
  }

 private:
  // mm/s: the scene's largest prescribed speed (the solver's setting).
  double speed_scale() const { return solver_.settings().speed_scale; }
  void frictions(const StepView& v, const std::vector<char>& active, std::vector<RowFriction>& out) const;
  // The Kuhn-Tucker and friction residuals of the settled solve.
  void measure(const StepView& v);

  const ContactDiscretization& disc_;
  SsnStepSolver solver_;
  const std::vector<ContactRow>* rows_ = nullptr;
  std::vector<SsnRowState> state_;
  std::vector<double> c_;  // N s/mm, per row: c_N, c_T
  std::vector<RowResult> results_;
  std::map<std::pair<int, Index>, SsnRowState> latest_;  // by row identity: the latest converged solve's
  // Of the last settled solve: the largest end-of-step penetration over
  // the element size, |lambda_N r| over (sum lambda_N) v_ref, the friction
  // conditions' largest violation over the bound (|lambda_T| above g,
  // a slipping row's |lambda_T + g sign gamma_T|) and a sticking row's
  // largest slip rate over v_ref.
  // The largest over the solves of step measured_step_.
  double primal_ = 0, complementarity_ = 0, friction_ = 0, stick_slip_ = 0;
  int measured_step_ = -1;
  int stick_ = 0, slip_ = 0;
  // The row of the largest of friction_ and stick_slip_ over the step's
  // solves, and why, in words (friction_violation_cause()).
  std::string cause_;
  // The solver's statistics summed over the step's solves (the midpoint
  // scheme's half step and its end; not over attempts not kept, whose
  // state restore_state undoes).
  SsnSolveStats step_stats_;
};

}  // namespace rpfem
