// The ipopt enforcement's own step solver (a StepSolver, as MFEM separates
// its ConstrainedSolver subclasses): the step's velocity field as a
// constrained minimization solved by Ipopt (Waechter and Biegler 2006)
// through its TNLP interface (step_nlp.hpp): the bodies' rigid-plastic
// functional, exactly as the kernel assembles it (the friction terms
// included), subject to one linear inequality per row: the gap at the end
// of the step, linearized in the velocities, must not be negative,
//   g_end / dt = gamma_N + g_from / dt >= 0        (pair_kinematics.hpp)
// The multipliers are the normal contact forces N = -lambda >= 0, and the
// solution meets the Kuhn-Tucker conditions of paper eq. 6 (gap >= 0,
// N >= 0, N gap = 0) to Ipopt's tolerance; after each solve the solver
// checks them itself (kkt()):
//   primal: max(0, -g_end) / h      (penetration per element size)
//   dual:   max(0, -N) / F          (F the element-force scale of the step)
//   complementarity: max |N g_end / dt| / (F v_ref)
//   stationarity: |R(u) + A^T lambda| / F
//   round_off: |R(u + one ulp) - R(u)| / F, the floor stationarity can reach
#pragma once
#include <IpIpoptApplication.hpp>

#include <string>
#include <vector>

#include "contact/pair_kinematics.hpp"
#include "io/case_file.hpp"
#include "ipopt/step_nlp.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

// One row as the solver sees it; force and end_gap are its outputs.
struct BoundRow {
  const PairKinematics* kin = nullptr;
  double h = 0;        // mm, local element size
  double force = 0;    // N, normal contact force (-lambda) of the last solve
  double end_gap = 0;  // mm, predicted gap at the end of the step
};

struct Kkt {
  double primal = 0, dual = 0, complementarity = 0, stationarity = 0;
  double round_off = 0;  // R's change under one-ulp changes of u, / F: stationarity's floor
};

class IpoptStepSolver final : public StepSolver {
 public:
  // force_scale (N): the objective's scale (what the contact could carry).
  IpoptStepSolver(const Scene& scene, CaseSection& settings, double force_scale);
  // The rows of the next solves (valid until the next call).
  void set_rows(std::vector<BoundRow>* rows) { rows_ = rows; }
  SolveOutcome solve(const StepView& v, StepProblem& problem, Vec& u) override;
  const Kkt& kkt() const { return kkt_; }
  int constraints() const { return used_; }
  void derived(std::vector<NamedValue>& out) const;

 private:
  // One Ipopt solve from `from`, its complementarity tolerance set from
  // the element-force scale `force` (N; 0 keeps the last).
  NlpOutcome optimize(StepProblem& problem, const std::vector<LinearRow>& rows, const Vec& from, double force);
  // The Kuhn-Tucker residuals of a solve into kkt_ and the rows' forces and
  // gaps; returns the element-force scale at the solution.
  double measure(const StepView& v, const StepProblem& problem, const std::vector<LinearRow>& rows,
                 const std::vector<int>& row_of, const NlpOutcome& out);

  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;
  std::vector<BoundRow>* rows_ = nullptr;
  double force_scale_ = 1, speed_scale_ = 0, mu_init_ = 1e-6;
  double round_off_force_ = 0;  // Newton's tol_force (relative residual)
  double last_scale_ = 0;       // N, the element-force scale of the last solve
  Kkt kkt_;
  int used_ = 0;
};

}  // namespace rpfem
