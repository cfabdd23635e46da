// Sparse LU by KLU (SuiteSparse; Davis and Palamadai Natarajan, ACM TOMS
// 37(3), 2010): block triangular form, AMD ordering, left-looking
// Gilbert-Peierls factorization with partial pivoting, no BLAS. A matrix of
// a pattern already factorized is refactorized with the pivots of its last
// full factorization (klu_refactor, no pivot search); a full factorization
// is redone where that refactorization fails or its pivots have lost more
// than a factor kRefactorRcondLoss of the full one's pivot ratio. A solve
// is refined iteratively against the matrix factorized (solve()).
#pragma once
#include <memory>

#include "core/types.hpp"

namespace rpfem {

class KluLU {
 public:
  // A refactorization whose pivot ratio min |U_kk| / max |U_kk| falls below
  // this share of the last full factorization's is done again in full.
  static constexpr double kRefactorRcondLoss = 1e-3;
  // Steps of iterative refinement in solve() at most.
  static constexpr int kRefinementSteps = 2;

  KluLU();
  ~KluLU();
  // Symbolic analysis of A's pattern (column major).
  void analyze(const SpMat& A);
  // Numeric factorization of A (the pattern analyze() saw); false if A is
  // singular.
  bool factorize(const SpMat& A);
  Vec solve(const Vec& b) const;
  // min |U_kk| / max |U_kk| with KLU's row scaling undone: the pivot ratio
  // of A itself (0 after a failed factorization).
  double rcond() const { return rcond_; }
  // Full factorizations and refactorizations done, for the benchmarks and
  // tests.
  int full_factorizations() const { return full_; }
  int refactorizations() const { return refactor_; }

 private:
  bool full(const SpMat& A);
  double pivot_ratio() const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double rcond_ = 0, full_rcond_ = 0;
  int full_ = 0, refactor_ = 0;
};

}  // namespace rpfem
