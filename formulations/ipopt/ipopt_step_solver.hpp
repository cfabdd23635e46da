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
// N >= 0, N gap = 0) to Ipopt's tolerance.
// Exact friction (a row's BoundRow::exact_bound g > 0; docs/theory.md,
// "Exact friction under ipopt"): the friction's dissipation g |gamma_T|,
// convex but not differentiable at gamma_T = 0, becomes smooth with a
// slack s >= 0 per row (the epigraph of |.|; Boyd and Vandenberghe 2004,
// sec. 4.1.3 and 6.1):
//   minimize g s  subject to  s - gamma_T >= 0,  s + gamma_T >= 0
// with gamma_T = a_T . u + t_0 linear in u as the gap is (t = (-n_y, n_x)
// for n). With p, q >= 0 the two rows' forces (-lambda), stationarity in s
// gives p + q = g, and in u the friction force on the slave along t
//   T = q - p,   |T| <= g,   T = -g sign(gamma_T) where gamma_T != 0
// (complementarity: p (s - gamma_T) = q (s + gamma_T) = 0): the exact law.
// A row whose slip rate no unknown moves, or moves only along its gap
// rate's direction (a slave node on the axis against a die not normal to
// it), is frictionless (docs/theory.md, "One direction").
// An interior point meets complementarity to its barrier parameter only:
// a row slipping slowly, |gamma_T| small, keeps q ~ mu / (2 |gamma_T|), and
// a row at the stick-slip transition both a slip rate and a distance
// g - |T| of order sqrt(mu). So a solve with exact friction is polished
// (polish(), after the solution polishing of Stellato et al. 2020, OSQP,
// Math. Prog. Comp. 12, sec. 4): its sets read from the solution (rows in
// contact, sticking, slipping either way), Newton's method on the
// program's Kuhn-Tucker conditions with those sets as equalities, and the
// result taken where it meets every inequality (the sets were right),
// else Ipopt's solution stands.
// After each solve the solver checks the conditions itself (kkt()):
//   primal: max(0, -g_end) / h      (penetration per element size; a
//           friction row's violation times dt / h)
//   dual:   max(0, -N) / F          (F the element-force scale of the step;
//           the friction rows' p, q alike)
//   complementarity: max |N g_end / dt| / (F v_ref), and the friction
//           rows' |p (s - gamma_T)|, |q (s + gamma_T)| / (F v_ref)
//   stationarity: |R(u) + A^T lambda| / F, with the slacks' g + lambda
//   round_off: |R(u + one ulp) - R(u)| / F, the floor stationarity can reach
#pragma once
#include <IpIpoptApplication.hpp>

#include <string>
#include <vector>

#include "contact/pair_kinematics.hpp"
#include "io/case_file.hpp"
#include "ipopt/mumps_analysis_reuse.hpp"
#include "ipopt/step_nlp.hpp"
#include "la/linear_solver.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

// One row as the solver sees it; force, end_gap, friction and
// friction_rows are its outputs.
struct BoundRow {
  const PairKinematics* kin = nullptr;
  double h = 0;        // mm, local element size
  // N: > 0, the row's friction is exact with this bound g (its slack and
  // two friction rows; 0: the objective's friction term, or none).
  double exact_bound = 0;
  double force = 0;    // N, normal contact force (-lambda) of the last solve
  double end_gap = 0;  // mm, predicted gap at the end of the step
  double friction = 0;  // N, exact friction: the force on the slave along t, q - p
  bool friction_rows = false;  // exact friction: its rows were in the last solve (else frictionless)
  double start_force = 0;  // N, the row's force in the last solve before this step's (its warm start)
  double start_friction = 0;  // N, its exact friction force there
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
  void set_rows(std::vector<BoundRow>* rows) {
    rows_ = rows, warm_next_ = loose_next_ = have_round_off_ = false, nlp_ = nullptr;
  }
  // The next solve re-solves the same rows after a change of the objective
  // alone (the friction bounds' fixed point): it starts from the last
  // solution's multipliers (the `warm_start` option); loose: to Ipopt's
  // loose_tol, not warm_tol (a pass far from the fixed point).
  void warm_next(bool loose) { warm_next_ = true, loose_next_ = loose; }
  // The next solve, a step's first, to the loose tol when warm: its bounds
  // are a prediction, and its solution only gives the next ones.
  void first_loose(bool loose) { loose_next_ = loose; }
  // The last solve was a warm pass to the loose tol.
  bool last_loose() const { return last_loose_; }
  SolveOutcome solve(const StepView& v, StepProblem& problem, Vec& u) override;
  const Kkt& kkt() const { return kkt_; }
  int warm_failures() const { return warm_failures_; }
  // MUMPS analyses run and reused (mumps_analysis_reuse.hpp) since this
  // solver was made.
  MumpsAnalysisCounts mumps_analyses() const;
  int constraints() const { return used_; }
  // Whether the last solve's solution was polished (exact friction).
  bool polished() const { return polished_; }
  void derived(std::vector<NamedValue>& out) const;

 private:
  // A relative Kuhn-Tucker residual within this multiple of the residual's
  // own round-off (Kkt::round_off, a one-sample estimate) is round-off.
  static constexpr double kRoundOffMultiple = 10;
  // One Ipopt solve of the program of nlp_rows_ from `from` (and from the
  // row multipliers `lambda` when warm-starting), its complementarity
  // tolerance set from the element-force scale `force` (N; 0 keeps the
  // last). The program of the last solve is solved again (ReOptimizeTNLP)
  // when it is the same problem with the same rows.
  // `from`: x = (u, s).
  NlpOutcome optimize(StepProblem& problem, const Vec& from, double force, const std::vector<double>* lambda = nullptr);
  // Ipopt's options for a start from given multipliers (warm_start_init_point,
  // warm_mu_init, warm_max_iter) or for the plain start; tol either way.
  void use_warm_start(bool on, double tol);
  // After a solve: its Kuhn-Tucker residuals measured (and the solve
  // repeated where only its complementarity tolerance was too loose);
  // whether its solution is taken, else result.reason says why not.
  bool conclude(const StepView& v, StepProblem& problem, NlpOutcome& out, SolveOutcome& result);
  // The Kuhn-Tucker residuals of a solve into kkt_ and the rows' forces and
  // gaps; returns the element-force scale at the solution.
  double measure(const StepView& v, const StepProblem& problem, const NlpOutcome& out);
  // The program's rows at the velocities u: the normal rows, then each
  // exact friction row's two (its slack's cost g into `cost`), with the
  // enforcement's row of each (row_of_, friction_of_); the start x = (u,
  // s) with s = |gamma_T(u)|.
  void build_rows(const StepView& v, const StepProblem& problem, const Vec& u, std::vector<LinearRow>& rows,
                  std::vector<double>& cost, Vec& x);
  // The rows' multipliers to start from: the forces (and exact friction
  // forces) of the rows' last solve, or their start_force.
  std::vector<double> row_multipliers(bool last_solve) const;
  // Exact friction: `out` made exact on its sets (ipopt_step_solver.hpp);
  // whether it was (else `out` is unchanged).
  bool polish(StepProblem& problem, NlpOutcome& out);

  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;
  std::vector<BoundRow>* rows_ = nullptr;
  double force_scale_ = 1, speed_scale_ = 0, mu_init_ = 1e-6;
  double tol_ = 1e-10;
  bool secant_after_cut_ = true;  // the scene's solver.secant_after_cut (StepNlp)
  double loose_tol_ = 1e-8;  // a loose pass's tol (its solution gives the next friction bounds only)
  double warm_mu_init_ = 0, warm_push_ = 0, warm_tol_ = 0;  // the warm start's barrier parameter, pushes, tol
  int max_iter_ = 500, warm_max_iter_ = 15;
  bool warm_start_ = true, warm_next_ = false, loose_next_ = false, last_loose_ = false;
  int warm_failures_ = 0;  // warm starts solved again from the plain start
  bool reuse_analysis_ = true;   // reuse_mumps_analysis
  bool polish_ = true;           // polish: exact friction's solutions made exact on their sets
  bool polished_ = false;
  LinearSolver polish_lu_;
  std::uint64_t polish_pattern_ = 0;  // a new pattern version per polish
  MumpsAnalysisCounts analyses_at_start_;
  std::vector<double> last_lambda_;  // the last solve's row multipliers
  // The program of this solve's last pass: its rows and unknowns (the
  // velocities'), the slacks' costs (N), the enforcement's row of each
  // normal row (row_of_) and of each slack (friction_of_; its rows are
  // the normal rows' count + 2 j and + 2 j + 1).
  Ipopt::SmartPtr<StepNlp> nlp_;
  std::vector<LinearRow> nlp_rows_;
  std::vector<double> nlp_cost_;
  std::vector<int> row_of_, friction_of_;
  Index nlp_unknowns_ = -1;
  double round_off_force_ = 0;  // Newton's tol_force (relative residual)
  double last_scale_ = 0;       // N, the element-force scale of the last solve
  Kkt kkt_;
  bool have_round_off_ = false;  // round_off_ taken in this solve's passes
  double round_off_ = 0;
  int used_ = 0;
};

}  // namespace rpfem
