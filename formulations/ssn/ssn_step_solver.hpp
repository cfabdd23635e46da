// The ssn enforcement's step solver (a StepSolver, as MFEM separates its
// ConstrainedSolver subclasses): the step's velocities u (reduced unknowns
// of the kernel's DofMap) and each row's normal and friction forces
// lambda_N, lambda_T solved together by a semi-smooth Newton method
// (primal-dual active set; Hueber, Stadler and Wohlmuth 2008; Popp et al.
// 2010) on
//   R(u) - sum_j (lambda_N,j a_N,j + lambda_T,j a_T,j) = 0   (equilibrium)
//   C_N,j = 0,  C_T,j = 0                                    (ncp.hpp)
// a_N,j and a_T,j the rows' gap and slip rates as weights on u (r_j =
// a_N,j . u + r0_j, gamma_T,j = a_T,j . u + t0_j). Each iteration solves
// the saddle-point system with the generalized derivative of the C's
//   [ K        -A_N^T    -A_T^T  ] [du ]     [residual]
//   [ C_N,u    C_N,N     0       ] [dlN] = - [C_N     ]
//   [ C_T,u    C_T,N     C_T,T   ] [dlT]     [C_T     ]
// by sparse LU (KLU or UMFPACK; its pattern fixed within a solve, so the
// analysis is reused), so the active, inactive, stick and slip sets follow
// from every iterate: no outer loop on the contact state or on the
// friction bounds. K is the kernel's tangent: the secant one in the first
// iteration and after an iteration whose line search cut the step, as the
// kernel's Newton does (solver/newton.hpp), but for a warm start (every
// row's forces from an earlier solve, none from hold_starting_sets()):
// its first iteration probes the consistent tangent, the velocities of the
// last solve being a usable field already, and is redone with the secant
// one (both counted) where the probe's full step fails the line search's
// test or moves a row into or out of contact (a landing: the start's
// tangent knows nothing of the new row, and core_in_sleeve's first
// landing under a consistent first step cycled on the released rows and
// stopped at 0.16 mm). Newton iterations against the secant start: ring
// at m = 1 1,335 -> 1,150, Test II die 1,086 -> 951, core_in_sleeve
// 729 -> 546 (mortar rows 1,113 -> 817); conditions met at every step.
// Globalization: a backtracking line search (Armijo) on the Lagrangian of
// the iterate's sets with the multipliers the Newton step gives,
//   L(u) = Pi(u) - sum_j (lambda+_N,j r_j(u) + lambda+_T,j gamma_T,j(u)),
// lambda+ = lambda + dlambda (Nocedal and Wright 2006, sec. 18.3): the
// velocity rows of the system give dL/du . du = -du^T K du, a descent
// direction wherever K is positive definite (the secant K always), and the
// rows' own functions are linear on the iterate's branches, so a step of
// length s leaves 1 - s of them. The sets are then updated at the new
// iterate. The residual norm |F| as the merit stalled: the secant step is
// no descent direction of it, and on the ring at m = 1 the search cut
// every step to 2^-12.
// Converged when |F| <= tol_force F_scale (F_scale the elements' force
// scale, as the kernel's), the sets did not change in the last iteration,
// and the velocity error (the last correction, times the contraction of
// two successive full steps when below 1/2; Deuflhard 2004, sec. 2.1) is
// at most tol_velocity |u|.
// Cycling: a row whose set changes kHoldAfter times in a solve (a node
// landing at the step's end with no force, a row at a neutral point) is
// held on its last branch; once the iteration converges on the sets held,
// a held row whose own set differs is released and the iteration goes on,
// so the solution met is the true one. In a cold solve (a run's first,
// the first after a remesh) each such round has the scene's iteration
// budget, as each contact pass of the other enforcements has. A row that
// lands and lifts off by turns under the friction factor is held grazing
// instead (ncp.hpp), and kept there if its friction force then lies within
// its bound and opposes its slip. A row that ends slipping along its own
// friction force is held sticking (at most kMaxRehold times). In a step
// that ends at a landing (StepView::at_landing), a row open at the start
// that lifts off from pressing and slipping at the friction factor's bound
// fails the solve at once: such a row may have no solution there, and the
// stepper tries the step past the landing (docs/theory.md, section 8).
// c_j (N s/mm) is the enforcement's (ssn_enforcement.hpp).
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_row.hpp"
#include "la/linear_solver.hpp"
#include "model/contact_formulation.hpp"
#include "solver/newton.hpp"
#include "ssn/ncp.hpp"

namespace rpfem {

struct SsnSettings {
  NewtonSettings newton;   // tolerances, iterations, line search: the scene's solver.*
  double c_normal = 1, c_tangential = 1;  // formulations.ssn.* (ssn_enforcement.hpp)
  LuMode lu = LuMode::Auto;
  double speed_scale = 1;  // mm/s: the scene's largest prescribed speed
  bool condense = true;    // formulations.ssn.condense
  bool augmented = true;   // formulations.ssn.augmented
};

// The row state the enforcement keeps between solves and reads after one.
struct SsnRowState {
  double lambda_n = 0, lambda_t = 0;  // N
  double end_gap_rate = 0, slip_rate = 0;  // mm/s, r and gamma_T at the solution
  double bound = 0;  // N, the friction bound g
  bool active = false, stick = false;
  bool grazing = false;  // in contact at zero force (ncp.hpp)
};

// Solver statistics of the last solve.
struct SsnSolveStats {
  int iterations = 0, halvings = 0, set_changes = 0;
  int holds = 0;  // rows held on their branch after cycling
  int rounds = 0;  // releases of held rows that started a new round (cold solves)
  int grazing = 0;  // rows ending grazing
  int condensed = 0;  // Newton steps solved with the rows condensed
  int augmented = 0;  // Newton steps solved by the augmented Lagrangian on K
  int rows = 0;  // rows in the solve
  double factor_seconds = 0;
};

class SsnStepSolver final : public StepSolver {
 public:
  // The frictions of the rows given which are active (the factor law's
  // k w and Coulomb's cap depend on the contact area).
  using Frictions = std::function<void(const StepView&, const std::vector<char>& active, std::vector<RowFriction>& out)>;
  explicit SsnStepSolver(SsnSettings s);
  // The rows of the next solves, their parameters c_N, c_T (N s/mm; row
  // j's at 2 j and 2 j + 1) and states
  // (warm start in, solution out); all valid until the next call.
  void set_rows(const std::vector<ContactRow>* rows, const std::vector<double>* c, std::vector<SsnRowState>* state,
                Frictions frictions) {
    rows_ = rows, c_ = c, state_ = state, frictions_ = std::move(frictions);
  }
  // The next solve holds every row on the set its starting forces give
  // until it converges on them, then releases the rows whose own set
  // differs, as it does rows that cycle: the first solve after a remesh,
  // its forces taken over from the old mesh (ContactRow::prior), where a
  // free start changed sets by the dozen per iteration and diverged.
  void hold_starting_sets() { hold_start_ = true; }
  SolveOutcome solve(const StepView& v, StepProblem& problem, Vec& u) override;
  const SsnSolveStats& stats() const { return stats_; }
  // The whole residual F and its generalized Jacobian (consistent K) at
  // x = (u, lambda_N,0, lambda_T,0, ...) for the rows in the solve (those
  // not free with an unknown to move), each on its own branch: what each
  // Newton iteration solves with (the tests check J against F's finite
  // differences).
  SpMat system(const StepView& v, StepProblem& problem, const Vec& x, Vec& F);
  // The rows in the last solve or system().
  std::size_t rows_in_solve() const { return red_.size(); }
  const SsnSettings& settings() const { return s_; }

 private:
  // One row in the reduced unknowns.
  struct Reduced {
    std::vector<std::pair<Index, double>> an, at;  // (dof, weight)
    double r0 = 0, t0 = 0;  // mm/s
    double cn = 0, ct = 0;  // N s/mm
    std::size_t row = 0;    // the enforcement's row
    // The gap and slip rates move along one direction of the unknowns (a
    // slave node on the axis or a symmetry plane against a die that is
    // not normal to it), or the slip rate along none (both sides on a
    // symmetry plane): the row cannot both hold its gap and stick, and
    // its forces act only through N n + T t along that direction. It is
    // held frictionless, its normal force carrying that component whole,
    // as `direct` records the reaction of such a node.
    // So is every row whose slave node has one free direction (a symmetry
    // plane, the axis, a prescribed component). A node-to-segment row of
    // such a node against the master's node on the same plane is one of
    // the above; a dual mortar row adds the master's nodes off the plane,
    // with weights from the master's curvature within the row's support
    // (at core_in_sleeve's corner on its symmetry plane 7e-5 of the
    // row's at 2.56 mm, 0.2 at 4.4 mm), so that sticking there can be
    // nearly dependent on the gap: held sticking after cycling, that row
    // kept a slip rate of 6e-8 mm/s while
    // its friction force grew by 1.3e3 N per iteration (kRegularization
    // far above the row's own compliance along its slip), and the solve
    // stopped at 2.56 mm. The row's friction force is the shear traction
    // at its node integrated with its test function, W_j tau(x_j) for tau
    // linear over the support (the dual basis; Wohlmuth 2000), and the
    // shear traction vanishes on a symmetry plane or the axis.
    bool one_direction = false;
    Index die_node = -1;  // a row against a die: its node
  };
  struct Iterate {
    Vec u;
    std::vector<double> ln, lt;
    Vec R;           // the elements' residual
    Vec F;           // the whole residual
    double norm = 0, scale = 0;
    double energy = 0;  // Pi(u)
    std::vector<double> r, g;  // per row: r and gamma_T (mm/s)
    std::vector<RowNcp> ncp;
    std::vector<char> sets;  // per row: 0 inactive, 1 slip, 2 stick
  };
  void reduce_rows(const StepView& v, const StepProblem& problem);
  // A solve's (or system()'s) start: its rows reduced, nothing held, the
  // patterns to hash.
  void start(const StepView& v, const StepProblem& problem);
  // The elements' residual R(u) of an iterate, then the whole F with the
  // rows' functions on their own branches or on those of `branch`.
  void forces(StepProblem& problem, Iterate& it);
  // The merit L at it.u with the multipliers ln, lt (it.energy: Pi(u)).
  double lagrangian(const Iterate& it, const std::vector<double>& ln, const std::vector<double>& lt) const;
  // Rows held on a branch (held_) keep it where `hold`.
  void rows(const StepView& v, Iterate& it, const Iterate* branch, bool hold = false);
  SpMat jacobian(const SpMat& K, const Iterate& it) const;
  bool newton_step(const SpMat& K, const Iterate& it, Vec& dx);
  // Whether the iterate's rows condense (ssn_newton_system.cpp), and the
  // Newton step with them condensed.
  bool condensable(const Iterate& it) const;
  bool condensed_step(const SpMat& K, const Iterate& it, Vec& dx);
  // The Newton step by the augmented Lagrangian on K where every row's
  // functions are an equation on du or on its own multiplier
  // (ssn_augmented_step.cpp); false where they are not, or it fails.
  bool augmented_step(const SpMat& K, const Iterate& it, Vec& dx);
  // The hash of a sparse matrix's pattern (FNV-1a over its index arrays).
  static std::uint64_t pattern_hash(const SpMat& A);
  // A = Q^T A Q in place, Q the rotation of the dofs of row_of's rows to
  // their (n, t) frames (condensed_step); false where the pattern does not
  // allow it.
  bool rotate_in_place(SpMat& A, const std::vector<int>& row_of) const;
  // Whether every row meets its own set's conditions at it to kRowGap and
  // kRowSlip (ssn_step_solver.cpp).
  bool rows_meet(const StepView& v, const Iterate& it) const;
  // Whether row j held grazing meets the friction law's hull at it.
  bool grazing_holds(const Iterate& it, std::size_t j) const;
  // The steps of solve(), in its order.
  // The solve's first iterate from u and the rows' saved forces: a row
  // with none that touches takes the force equilibrium asks of it, a
  // slipping one its present bound; cold where no row has forces from
  // an earlier solve or after hold_starting_sets(), warm where every row
  // has (the first iteration then probes the consistent tangent).
  struct Start {
    Iterate x;
    bool cold = true, warm = true;
  };
  Start first_iterate(const StepView& v, StepProblem& problem, const Vec& u);
  // The backtracking line search along dx from x (the opening comment
  // above: Armijo on the Lagrangian of x's sets): the trial
  // at step s on its own sets; redo where the probe of the consistent
  // tangent failed its test.
  struct Search {
    Iterate trial;
    double s = 1;
    bool redo = false;
  };
  Search line_search(const StepView& v, StepProblem& problem, const Iterate& x, const Vec& dx, bool keep_full_step,
                     bool probe);
  // Why the solve stops at a row landing at the step's end that lifts off
  // from pressing at the friction factor's bound; empty where none does.
  std::string landing_lift_off(const StepView& v, const Iterate& x, const Iterate& trial) const;
  // Rows changing set by turns from x to trial (changes rows in all) held
  // on their branch after kHoldAfter changes.
  void hold_cycling(const Iterate& x, const Iterate& trial, int changes);
  // At x, converged on the sets held: free (a copy of x) on its own sets,
  // and the held rows whose own set differs released or held on it
  // again; a row slipping along its own force held sticking (stuck).
  // The rows released: none where x is the solution.
  int release(const StepView& v, const Iterate& x, Iterate& free, bool round_off, bool& stuck);
  // The solution x into u and the rows' states.
  void store(const Iterate& x, Vec& u);

  SsnSettings s_;
  const std::vector<ContactRow>* rows_ = nullptr;
  const std::vector<double>* c_ = nullptr;
  std::vector<SsnRowState>* state_ = nullptr;
  Frictions frictions_;
  std::vector<Reduced> red_;
  std::vector<RowFriction> friction_;  // per enforcement row
  std::vector<char> active_rows_;      // per enforcement row, for frictions_
  bool hold_start_ = false;  // hold_starting_sets()
  // Per row of the solve: its set changes, and the branch it is held on
  // after kHoldAfter of them (ssn_step_solver.cpp).
  std::vector<int> flips_, normal_flips_, reholds_;
  // Per row of the solve: its node is in contact with another die too, at
  // the last set update.
  std::vector<char> shared_;
  std::vector<std::optional<RowNcp>> held_;
  LinearSolver lu_, cholesky_, augmented_cholesky_;
  std::uint64_t condensed_hash_ = 0, condensed_version_ = 0;
  bool saddle_hashed_ = false, condensed_hashed_ = false, augmented_hashed_ = false;  // in this solve
  std::uint64_t augmented_hash_ = 0, augmented_version_ = 0;
  std::uint64_t pattern_hash_ = 0, pattern_version_ = 0;
  SsnSolveStats stats_;
};

}  // namespace rpfem
