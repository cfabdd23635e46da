// CHOLMOD's Cholesky factorization of a symmetric matrix, handed to
// CHOLMOD already in the factor's order.
//
// Given the lower triangle of A (stype < 0, as Eigen's wrapper passes it)
// and a fill-reducing ordering P, cholmod_factorize first forms
// tril(P A P^T) by two transposes, triu(P A P^T) and then its transpose
// (CHOLMOD/Cholesky/cholmod_factorize.c), at every factorization: 6.7 % of
// a Newton iteration at 1e5 unknowns, in cholmod_transpose_sym and the
// page faults of its fresh copies (docs/decisions.md, "Linear algebra and the
// element loops"). Given a lower triangle in the natural ordering it factorizes
// the matrix as given ("the fastest option for the natural ordering", same
// file).
//
// CholmodLLT therefore analyzes A as CHOLMOD would (its ordering,
// postordered), then keeps that ordering itself and declares the factor's
// ordering natural: each factorization gathers tril(P A P^T) from A's
// values through value positions found once per analysis, and each solve
// permutes b and x around CHOLMOD's, as cholmod_solve does with the
// factor's own permutation. CHOLMOD factorizes the same matrix S with the
// same symbolic factor, so the factor and the solutions are its own to the
// bit (tests/unit: against Eigen's CholmodDecomposition). A simplicial
// factor (CHOLMOD's choice under Mode::Auto) takes CHOLMOD's own path,
// which needs a transpose in either ordering (cholmod_llt.cpp).
#pragma once
#include <cholmod.h>

#include <memory>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

// The kernel's CHOLMOD options, set on a CholmodLLT at its construction
// (and on a bare CHOLMOD factorization compared with it: the bench, the
// tests): no printing (the kernel never prints), and the fill-reducing
// ordering by AMD only, postordered. CHOLMOD's default tries METIS too
// where AMD's fill is large, and METIS installs its own SIGTERM and SIGINT
// handlers while it runs (GKlib's gk_sigtrap), so a run could not be
// stopped during an analysis (docs/decisions.md, "Linear algebra and the
// element loops" for what it costs).
void set_kernel_options(cholmod_common& c);

class CholmodLLT {
 public:
  enum class Mode { Supernodal, Simplicial, Auto };  // CHOLMOD's supernodal switch
  explicit CholmodLLT(Mode mode);
  ~CholmodLLT();
  CholmodLLT(const CholmodLLT&) = delete;
  CholmodLLT& operator=(const CholmodLLT&) = delete;

  // The symbolic analysis of A's pattern (its lower triangle: A may hold
  // both). Every later factorize() takes a matrix of this very pattern
  // (its value positions are the gather's); one of another size or
  // number of stored entries is a std::logic_error. Throws
  // std::runtime_error where CHOLMOD's analysis fails (out of memory).
  void analyze(const SpMat& A);
  // The numeric factorization; false where A is not positive definite.
  bool factorize(const SpMat& A);
  // x = A^-1 b by the last successful factorization.
  Vec solve(const Vec& b);
  // CHOLMOD's reciprocal condition estimate of the factor (cholmod_rcond).
  double rcond();
  // Whether the last analysis chose a supernodal factor.
  bool supernodal() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<int> perm_;    // the factor's ordering: row k of P A P^T is A's row perm_[k]; empty: CHOLMOD's own path
  std::vector<int> gather_;  // S's values: S.value[k] = A.value[gather_[k]]
  SpMat S_;                  // tril(P A P^T), the matrix CHOLMOD factorizes
  Index rows_ = -1, nonzeros_ = -1;  // the analyzed pattern's (a cheap check of it)
};

}  // namespace rpfem
