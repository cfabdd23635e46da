#include "la/linear_solver.hpp"

#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/timing.hpp"
#include "la/cholmod_llt.hpp"
#include "la/klu_lu.hpp"

namespace rpfem {

namespace {

// Eigen's wrapper keeps the factors protected: this reads its condition
// estimate.
struct LU : Eigen::UmfPackLU<SpMat> {
  // UMFPACK's own Info[UMFPACK_RCOND] is of the row-scaled matrix R A; the
  // same estimate for A itself: P R A Q = L U gives P A Q = (S L S^-1)(S U)
  // with S = diag(1 / r_P[k]), so U_kk / r_P[k] is the unscaled diagonal
  // (UMFPACK User Guide, umfpack_get_numeric: Rs and do_recip).
  double rcond() {
    const int n = static_cast<int>(rows());
    std::vector<int> P(n);
    std::vector<double> D(n), Rs(n);
    int recip = 0;
    if (umfpack_di_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, P.data(), nullptr, D.data(),
                               &recip, Rs.data(), m_numeric) != UMFPACK_OK)
      return 0.0;
    double lo = INFINITY, hi = 0;
    for (int k = 0; k < n; ++k) {
      const double r = recip ? Rs[P[k]] : 1.0 / Rs[P[k]];
      const double d = std::abs(D[k] / r);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    return hi > 0 ? lo / hi : 0.0;
  }
};

}  // namespace

struct LinearSolver::Impl {
  CholmodLLT llt;
  LU lu;
  KluLU klu;
  LuMode lu_mode;
  std::uint64_t llt_pattern = 0, lu_pattern = 0;  // 0: not analyzed
  bool use_lu = false;
  bool lu_is_klu = false;  // the LU analysis and factorization held are KLU's
  Impl(CholeskyMode mode, LuMode l)
      : llt(mode == CholeskyMode::Simplicial ? CholmodLLT::Mode::Simplicial
            : mode == CholeskyMode::Auto     ? CholmodLLT::Mode::Auto
                                             : CholmodLLT::Mode::Supernodal),
        lu_mode(l) {}
};

LinearSolver::LinearSolver(LinearSolverChoice choice, CholeskyMode mode, LuMode lu)
    : impl_(std::make_unique<Impl>(mode, lu)), choice_(choice) {}
LinearSolver::~LinearSolver() = default;

bool LinearSolver::factorize(const SpMat& A, bool symmetric, std::uint64_t pattern_version) {
  auto t0 = Clock::now();
  const bool try_llt = choice_ == LinearSolverChoice::Cholmod || (choice_ == LinearSolverChoice::Auto && symmetric);
  ++stats_.factorizations;
  held_pattern_ = 0;
  if (try_llt) {
    if (impl_->llt_pattern != pattern_version) {
      impl_->llt.analyze(A);
      impl_->llt_pattern = pattern_version;
      ++stats_.analyses;
      stats_.analyze_seconds += seconds_since(t0);
      t0 = Clock::now();
    }
    const bool ok = impl_->llt.factorize(A);
    ++stats_.by_cholmod;
    stats_.factor_seconds += seconds_since(t0);
    if (ok) {
      impl_->use_lu = false;
      stats_.last_solver = "cholmod";
      note_rcond(impl_->llt.rcond());
      held_pattern_ = pattern_version, held_rows_ = A.rows();
      return true;
    }
    if (choice_ == LinearSolverChoice::Cholmod) {
      note_rcond(0.0);  // not positive definite: singular as far as Cholesky can tell
      return false;
    }
    ++stats_.cholesky_fallbacks;  // indefinite: fall through to LU
    t0 = Clock::now();
  }
  const bool klu = impl_->lu_mode == LuMode::Klu || (impl_->lu_mode == LuMode::Auto && A.rows() < kKluMaxRows);
  if (impl_->lu_pattern != pattern_version || impl_->lu_is_klu != klu) {
    if (klu)
      impl_->klu.analyze(A);
    else
      impl_->lu.analyzePattern(A);
    impl_->lu_pattern = pattern_version;
    impl_->lu_is_klu = klu;
    ++stats_.analyses;
    stats_.analyze_seconds += seconds_since(t0);
    t0 = Clock::now();
  }
  const bool ok = klu ? impl_->klu.factorize(A) : (impl_->lu.factorize(A), impl_->lu.info() == Eigen::Success);
  stats_.factor_seconds += seconds_since(t0);
  impl_->use_lu = true;
  stats_.last_solver = klu ? "klu" : "umfpack";
  ++(klu ? stats_.by_klu : stats_.by_umfpack);
  if (!ok) {
    note_rcond(0.0);  // singular
    return false;
  }
  note_rcond(klu ? impl_->klu.rcond() : impl_->lu.rcond());
  held_pattern_ = pattern_version, held_rows_ = A.rows();
  return true;
}

bool LinearSolver::solve_reads_matrix() const { return impl_->use_lu && !impl_->lu_is_klu; }

bool LinearSolver::holds(std::uint64_t pattern_version, Index rows) const {
  return held_pattern_ != 0 && held_pattern_ == pattern_version && held_rows_ == rows;
}

void LinearSolver::note_rcond(double rcond) {
  stats_.last_rcond = std::isfinite(rcond) ? rcond : 0.0;
  stats_.min_rcond = std::min(stats_.min_rcond, stats_.last_rcond);
}

Vec LinearSolver::solve(const Vec& b) {
  const auto t0 = Clock::now();
  Vec x;
  if (impl_->use_lu)
    x = impl_->lu_is_klu ? impl_->klu.solve(b) : Vec(impl_->lu.solve(b));
  else
    x = impl_->llt.solve(b);
  stats_.solve_seconds += seconds_since(t0);
  return x;
}

}  // namespace rpfem
