#include "la/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>
#include <chrono>

namespace rpfem {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

struct LinearSolver::Impl {
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> llt;
  Eigen::UmfPackLU<SpMat> lu;
  std::uint64_t llt_pattern = 0, lu_pattern = 0;  // 0: not analyzed
  bool use_lu = false;
  Impl() { llt.cholmod().print = 0; }  // the kernel never prints
};

LinearSolver::LinearSolver(LinearSolverChoice choice) : impl_(std::make_unique<Impl>()), choice_(choice) {}
LinearSolver::~LinearSolver() = default;

bool LinearSolver::factorize(const SpMat& A, bool symmetric, std::uint64_t pattern_version) {
  auto t0 = std::chrono::steady_clock::now();
  const bool try_llt = choice_ == LinearSolverChoice::Cholmod || (choice_ == LinearSolverChoice::Auto && symmetric);
  ++stats_.factorizations;
  if (try_llt) {
    if (impl_->llt_pattern != pattern_version) {
      impl_->llt.analyzePattern(A);
      impl_->llt_pattern = pattern_version;
      ++stats_.analyses;
      stats_.analyze_seconds += seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
    }
    impl_->llt.factorize(A);
    stats_.factor_seconds += seconds_since(t0);
    if (impl_->llt.info() == Eigen::Success) {
      impl_->use_lu = false;
      stats_.last_solver = "cholmod";
      return true;
    }
    if (choice_ == LinearSolverChoice::Cholmod) return false;
    ++stats_.cholesky_fallbacks;  // indefinite: fall through to LU
    t0 = std::chrono::steady_clock::now();
  }
  if (impl_->lu_pattern != pattern_version) {
    impl_->lu.analyzePattern(A);
    impl_->lu_pattern = pattern_version;
    ++stats_.analyses;
    stats_.analyze_seconds += seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
  }
  impl_->lu.factorize(A);
  stats_.factor_seconds += seconds_since(t0);
  impl_->use_lu = true;
  stats_.last_solver = "umfpack";
  return impl_->lu.info() == Eigen::Success;
}

Vec LinearSolver::solve(const Vec& b) {
  const auto t0 = std::chrono::steady_clock::now();
  Vec x = impl_->use_lu ? Vec(impl_->lu.solve(b)) : Vec(impl_->llt.solve(b));
  stats_.solve_seconds += seconds_since(t0);
  return x;
}

}  // namespace rpfem
