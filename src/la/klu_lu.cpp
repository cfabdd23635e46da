#include "la/klu_lu.hpp"

#include <klu.h>

#include <algorithm>
#include <cmath>

namespace rpfem {

struct KluLU::Impl {
  SpMat matrix;  // the pattern analyzed, the values factorized (the refinement's residuals)
  klu_common common;
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  int n = 0;
  Impl() {
    klu_defaults(&common);
    // Rows scaled by their sums of magnitudes, as UMFPACK scales them by
    // default (UMFPACK_SCALE_SUM). KLU's default, the largest magnitude,
    // stalled Newton at the residual's round-off floor on the stiffness
    // contrast of 3.8e5 (cases/extremes/stiffness_contrast.toml,
    // contrast_1e7) that UMFPACK and KLU with sum scaling solve.
    common.scale = 1;
  }
  ~Impl() { clear(); }
  void clear_numeric() {
    if (numeric) klu_free_numeric(&numeric, &common);
  }
  void clear() {
    clear_numeric();
    if (symbolic) klu_free_symbolic(&symbolic, &common);
  }
};

namespace {
// KLU takes the arrays as non-const; it reads them only.
int* outer(const SpMat& A) { return const_cast<int*>(A.outerIndexPtr()); }
int* inner(const SpMat& A) { return const_cast<int*>(A.innerIndexPtr()); }
double* values(const SpMat& A) { return const_cast<double*>(A.valuePtr()); }
}  // namespace

KluLU::KluLU() : impl_(std::make_unique<Impl>()) {}
KluLU::~KluLU() = default;

void KluLU::analyze(const SpMat& A) {
  impl_->clear();
  impl_->matrix = A;  // compressed: the pattern each factorization's values fill
  impl_->matrix.makeCompressed();
  impl_->n = static_cast<int>(A.rows());
  impl_->symbolic = klu_analyze(impl_->n, outer(impl_->matrix), inner(impl_->matrix), &impl_->common);
  rcond_ = full_rcond_ = 0;
}

bool KluLU::full(const SpMat& A) {
  impl_->clear_numeric();
  ++full_;
  impl_->numeric = klu_factor(outer(A), inner(A), values(A), impl_->symbolic, &impl_->common);
  if (!impl_->numeric || impl_->common.status != KLU_OK) {
    impl_->clear_numeric();
    rcond_ = full_rcond_ = 0;
    return false;
  }
  rcond_ = full_rcond_ = pivot_ratio();
  return true;
}

bool KluLU::factorize(const SpMat& matrix) {
  if (!impl_->symbolic) return rcond_ = 0, false;
  // The values into the analyzed pattern (no allocation in a Newton
  // iteration); a matrix left uncompressed (inserted into) is copied whole.
  SpMat& A = impl_->matrix;
  if (matrix.isCompressed() && matrix.nonZeros() == A.nonZeros())
    std::copy(matrix.valuePtr(), matrix.valuePtr() + matrix.nonZeros(), A.valuePtr());
  else
    A = matrix, A.makeCompressed();
  if (impl_->numeric && full_rcond_ > 0) {
    ++refactor_;
    if (klu_refactor(outer(A), inner(A), values(A), impl_->symbolic, impl_->numeric, &impl_->common) &&
        impl_->common.status == KLU_OK) {
      rcond_ = pivot_ratio();
      if (rcond_ >= kRefactorRcondLoss * full_rcond_) return true;
    }
  }
  return full(A);
}

// x = (LU)^-1 b, then iterative refinement as UMFPACK does by default
// (UMFPACK User Guide, Control[UMFPACK_IRSTEP] = 2; Higham, Accuracy and
// Stability of Numerical Algorithms, 2nd ed., ch. 12): r = b - A x,
// x += (LU)^-1 r, at most kRefinementSteps times, while the residual
// falls by half at least: a solve as accurate as UMFPACK's on the
// ill-conditioned tangents of a large penalty or stiffness contrast.
Vec KluLU::solve(const Vec& b) const {
  const auto apply_inverse = [&](Vec& v) {
    klu_solve(impl_->symbolic, impl_->numeric, impl_->n, 1, v.data(), &impl_->common);
  };
  Vec x = b;
  apply_inverse(x);
  Vec r = b - impl_->matrix * x;
  double norm = r.lpNorm<Eigen::Infinity>();
  for (int step = 0; step < kRefinementSteps && norm > 0; ++step) {
    Vec dx = r;
    apply_inverse(dx);
    const Vec y = x + dx;
    Vec ry = b - impl_->matrix * y;
    const double ny = ry.lpNorm<Eigen::Infinity>();
    if (!(ny < 0.5 * norm)) break;
    x = y, r.swap(ry), norm = ny;
  }
  return x;
}

// KLU factors (R^-1 A)(P, Q) = L U + F, R the row scaling (Rs) and F the
// off-diagonal blocks of the block triangular form (KLU User Guide,
// klu_factor); U_kk * Rs[P[k]] is the pivot of A's own row P[k].
double KluLU::pivot_ratio() const {
  const klu_numeric* num = impl_->numeric;
  double lo = INFINITY, hi = 0;
  for (int k = 0; k < impl_->n; ++k) {
    const double r = num->Rs ? num->Rs[num->Pnum[k]] : 1.0;
    const double d = std::abs(static_cast<const double*>(num->Udiag)[k] * r);
    lo = std::min(lo, d), hi = std::max(hi, d);
  }
  return hi > 0 && std::isfinite(lo) ? lo / hi : 0.0;
}

}  // namespace rpfem
