// Sparse direct solves: CHOLMOD (LL^T, supernodal or simplicial) for a symmetric positive
// definite tangent, LU (KLU or UMFPACK) for a nonsymmetric one (frictional
// contact) or when Cholesky finds the matrix indefinite. The symbolic analysis is
// reused while the sparsity pattern is unchanged.
#pragma once
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "core/types.hpp"

namespace rpfem {

// Auto: CHOLMOD for a symmetric tangent, else LU; Cholmod, Lu: that one
// always.
enum class LinearSolverChoice { Auto, Cholmod, Lu };
// CHOLMOD's factorization: supernodal (dense blocks through the BLAS) or
// simplicial (column by column, no BLAS). Factor + solve of a tangent
// (bench BM_Cholmod*, Debian's reference BLAS, CHOLMOD's OpenMP loops on
// one thread as linear_solver.cpp runs them): simplicial 1.4 and 1.1 times
// faster at 1e3 and 3e3 unknowns, even at 1e4, 1.5 times slower at 1e5
// (docs/decisions.md, "Linear algebra and the element loops").
// Auto: CHOLMOD's own choice per analysis (supernodal where the
// factorization's flops per nonzero of L reach 40, Common->supernodal_switch).
enum class CholeskyMode { Supernodal, Simplicial, Auto };
// The LU factorization (nonsymmetric tangents, Cholesky's fallback):
// KLU (la/klu_lu.hpp: left-looking, no BLAS, refactorizing with the last
// pivots) or UMFPACK (multifrontal, its dense fronts through the BLAS, a
// pivot search at every factorization). Factor + solve of a tangent
// (bench BM_KluRefactor, BM_Umfpack; reference BLAS): KLU 1.9, 1.4 and
// 1.04 times faster at 1e3, 3e3 and 1e4 unknowns, 1.4 times slower at
// 2.9e4 (docs/decisions.md, "Linear algebra and the element loops"). Auto: KLU
// below kKluMaxRows rows, else UMFPACK.
enum class LuMode { Auto, Klu, Umfpack };
inline constexpr long kKluMaxRows = 10000;

// Below this reciprocal condition estimate a tangent is ill-conditioned for
// double precision: a direct solve's relative error is bounded by about
// eps / rcond, 1 % at 100 eps (2.2e-14), so a Newton correction keeps at
// most two correct digits. The estimate is rough (a pivot ratio): a
// problem can run out of precision above it (its residual's round-off
// floor above the tolerance, newton.hpp's `stalled`).
inline constexpr double kIllConditionedRcond = 100 * std::numeric_limits<double>::epsilon();

struct LinearSolveStats {
  int analyses = 0;          // symbolic analyses done
  int factorizations = 0;
  int cholesky_fallbacks = 0;  // Cholesky failed, LU used instead
  // Factorizations by each library (a Cholesky fallback counts in both).
  int by_cholmod = 0, by_klu = 0, by_umfpack = 0;
  double analyze_seconds = 0, factor_seconds = 0, solve_seconds = 0;
  std::string last_solver;   // "cholmod", "klu" or "umfpack"
  // A rough reciprocal condition number of the last factorization, from
  // its factor's diagonal (CHOLMOD's cholmod_rcond: (min L_ii / max L_ii)^2;
  // LU: min |U_ii| / max |U_ii| with its row scaling undone), and the least
  // since reset_rcond() (infinity if nothing was factorized since; 0 after a
  // factorization that found the matrix singular).
  double last_rcond = 0, min_rcond = INFINITY;
};

class LinearSolver {
 public:
  explicit LinearSolver(LinearSolverChoice choice = LinearSolverChoice::Auto,
                        CholeskyMode mode = CholeskyMode::Supernodal, LuMode lu = LuMode::Auto);
  ~LinearSolver();
  // Factorizes A; symmetric tells whether A is symmetric (then only CHOLMOD
  // is tried under Auto). pattern_version identifies A's sparsity pattern.
  // Returns false if A is singular.
  bool factorize(const SpMat& A, bool symmetric, std::uint64_t pattern_version);
  Vec solve(const Vec& b);
  // Whether a factorization of a matrix with this pattern (and as many
  // rows as b) is held: the last factorize() of that pattern succeeded.
  bool holds(std::uint64_t pattern_version, Index rows) const;
  // Whether solve() reads the factorized matrix itself, which must then
  // stay as factorized: UMFPACK's iterative refinement reads the caller's
  // values (Eigen's UmfPackLU holds a reference); CHOLMOD's solves read the
  // factor only, and KLU refines with its own copy.
  bool solve_reads_matrix() const;
  const LinearSolveStats& stats() const { return stats_; }
  void reset_rcond() { stats_.min_rcond = INFINITY; }

 private:
  void note_rcond(double rcond);
  struct Impl;
  std::unique_ptr<Impl> impl_;
  LinearSolverChoice choice_;
  LinearSolveStats stats_;
  std::uint64_t held_pattern_ = 0;  // 0: no factorization held
  Index held_rows_ = 0;
};

}  // namespace rpfem
