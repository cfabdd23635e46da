// "auglag": the augmented Lagrangian (Bertsekas 1982; Simo and Laursen
// 1992; Laursen 2002, sec. 5.3), the method between the penalty and exact
// enforcement. Each row carries the term of contact/row_terms.hpp with its
// multiplier lambda (N):
//   N = max(0, lambda - beta r),   E = N^2 / (2 beta)
// r the predicted end-of-step gap rate. Newton solves the step with lambda
// fixed; then Uzawa's update lambda <- N (the first-order multiplier
// update) and the step is solved again, until the Kuhn-Tucker residuals
// hold:
//   primal: max(0, -g_end) / h <= tolerance           (default 1e-9)
//   complementarity: max |N g_end / dt| / (sum N v_ref) <= complementarity_tolerance (1e-8)
// (dual feasibility N >= 0 holds by construction; stationarity is Newton's
// residual). Each update shrinks the penetration by about K / (K + beta),
// K the stiffness the contact sees, so beta can be far below the
// penalty's (default 1e-2 of it) and Newton's matrices stay well
// conditioned. The multipliers start each solve from the row's last
// normal force (by the row's identity), so a step whose contact barely
// changed needs one or two updates. Friction and the contact state as the
// penalty's (contact/regularized_rows.hpp), with N the multiplier-shifted
// normal force.
#pragma once
#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "contact/regularized_rows.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

class AugLagEnforcement final : public RegularizedEnforcement {
 public:
  AugLagEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc);
  std::string name() const override { return "auglag"; }
  void begin_step(const StepView& v, const std::vector<ContactRow>& rows) override;
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  // The penalty's tangent; its gaps are measured from the velocities, to a
  // tenth of the tolerance: Newton's velocity error at most kTolVelocity.
  TangentKind tangent() const override {
    TangentKind k = rows_.tangent();
    k.tol_velocity = kTolVelocity;
    return k;
  }
  void columns(std::vector<NamedValue>& out) const override;
  // The deeper of the predicted end-of-step gap's (primal_) and the
  // configuration's (the rows' gaps as the solve starts: the penalty's
  // max_penetration_rel), so a run warns of a depth the predicted gaps do
  // not see (a slave sliding past a master node, a step that started
  // inside).
  std::optional<double> penetration_rel() const override { return std::max(primal_, depth_); }
  void derived(std::vector<NamedValue>& out) const override;
  std::any save_state() const override {
    return save_members(RegularizedEnforcement::save_state(), lambda_, solve_augmentations_, augmentations_, step_,
                        primal_, complementarity_, last_step_, omega_);
  }
  void restore_state(const std::any& saved) override {
    std::any base;
    restore_members(saved, base, lambda_, solve_augmentations_, augmentations_, step_, primal_, complementarity_,
                    last_step_, omega_);
    RegularizedEnforcement::restore_state(base);
  }

 private:
  // The residuals of the last solve into primal_ and complementarity_.
  void measure(const StepView& v, const std::vector<Vec2>& vel);
  // The next multipliers from this solve's forces (Uzawa's update,
  // accelerated).
  void update_multipliers();
  static constexpr double kTolVelocity = 1e-10;

  std::map<std::pair<int, Index>, double> lambda_;  // N, by row identity
  double tol_primal_ = 0, tol_compl_ = 0, speed_scale_ = 0;
  int max_augmentations_ = 0;
  int solve_augmentations_ = 0;  // in this solve (max_augmentations bounds it)
  int augmentations_ = 0;        // in this step (all its solves)
  int step_ = -1;
  double primal_ = 0, complementarity_ = 0;
  double depth_ = 0;  // the rows' deepest gap as the solve starts, over h
  // Aitken's relaxation of the update: the last update's residual N - lambda
  // per row and its factor.
  std::vector<double> last_step_;
  double omega_ = 1;
  bool aitken_ = true;  // false: plain Uzawa (omega = 1)
};

}  // namespace rpfem
