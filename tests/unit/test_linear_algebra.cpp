// Nodal frames and elimination, fixed-pattern assembly, the sparse direct
// solvers, and the Newton solver on a problem with a known minimizer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <Eigen/CholmodSupport>

#include "fem/dof_map.hpp"
#include "la/cholmod_llt.hpp"
#include "la/inline_openmp.hpp"
#include "la/klu_lu.hpp"
#include "la/linear_solver.hpp"
#include "la/sparse_assembler.hpp"
#include "solver/newton.hpp"

using namespace rpfem;

TEST(DofMap, RotatedFrameKeepsTangentFree) {
  const Vec2 n = Vec2(1, 1).normalized();
  DofMap d(3, {{0, Vec2(1, 0), 2.0}, {0, Vec2(0, 1), -1.0}, {1, n, 0.5}});
  EXPECT_EQ(d.frame(0).nfree, 0);
  EXPECT_EQ(d.frame(1).nfree, 1);
  EXPECT_EQ(d.frame(2).nfree, 2);
  EXPECT_EQ(d.num_free(), 3);
  Vec u(3);
  u << 0.7, -0.2, 0.4;
  EXPECT_NEAR((d.velocity(0, u) - Vec2(2, -1)).norm(), 0, 1e-15);
  EXPECT_NEAR(d.velocity(1, u).dot(n), 0.5, 1e-15);  // the constraint holds for any u
  std::vector<Vec2> v;
  d.expand(u, v);
  EXPECT_NEAR((d.reduce(v) - u).norm(), 0, 1e-14);
}

TEST(DofMap, RejectsConflicts) {
  EXPECT_THROW(DofMap(1, {{0, Vec2(1, 0), 1.0}, {0, Vec2(-1, 0), 1.0}}), std::invalid_argument);
  EXPECT_NO_THROW(DofMap(1, {{0, Vec2(1, 0), 1.0}, {0, Vec2(-1, 0), -1.0}}));  // the same, restated
  EXPECT_THROW(DofMap(1, {{0, Vec2(1, 0), 0.0}, {0, Vec2(0, 1), 0.0}, {0, Vec2(1, 1), 0.0}}),
               std::invalid_argument);
}

TEST(SparseAssembler, MatchesDenseTransformedAssembly) {
  // Two quads sharing an edge; node 1 in a rotated frame, node 0 fixed.
  std::vector<std::array<Index, 4>> quads{{0, 1, 2, 3}, {1, 4, 5, 2}};
  const Vec2 n = Vec2(0.6, 0.8);
  DofMap d(6, {{0, Vec2(1, 0), 0}, {0, Vec2(0, 1), 0}, {1, n, 0}});
  SparseAssembler A;
  A.build(d, quads, {});
  Eigen::Matrix<double, 8, 8> K1 = Eigen::Matrix<double, 8, 8>::Random(), K2 = Eigen::Matrix<double, 8, 8>::Random();
  A.add(quads[0].data(), 4, K1.data());
  A.add(quads[1].data(), 4, K2.data());
  // Dense reference: T (12 x nfree) with K = sum scatter, A = T^T K T.
  Eigen::MatrixXd Kfull = Eigen::MatrixXd::Zero(12, 12), T = Eigen::MatrixXd::Zero(12, d.num_free());
  auto scatter = [&](const std::array<Index, 4>& q, const Eigen::Matrix<double, 8, 8>& K) {
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) Kfull.block<2, 2>(2 * q[a], 2 * q[b]) += K.block<2, 2>(2 * a, 2 * b);
  };
  scatter(quads[0], K1);
  scatter(quads[1], K2);
  for (Index i = 0; i < 6; ++i)
    for (int k = 0; k < d.frame(i).nfree; ++k) T.block<2, 1>(2 * i, d.frame(i).dof[k]) = d.frame(i).T.col(k);
  const Eigen::MatrixXd ref = T.transpose() * Kfull * T;
  EXPECT_LT((Eigen::MatrixXd(A.matrix()) - ref).norm(), 1e-12 * ref.norm());
  const auto v0 = A.pattern_version();
  A.build(d, quads, {{0, 5}});
  EXPECT_GT(A.pattern_version(), v0);
}

namespace {
// The n x n tridiagonal matrix with `diag` on the diagonal, `lower` below
// and `upper` above it.
SpMat tridiagonal(long n, double lower, double diag, double upper) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, diag);
    if (i > 0) t.emplace_back(i, i - 1, lower), t.emplace_back(i - 1, i, upper);
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}
}  // namespace

TEST(LinearSolver, CholmodAndUmfpackSolve) {
  const int n = 50;
  const SpMat A = tridiagonal(n, -1.0, 4.0, -1.0);
  const Vec b = Vec::LinSpaced(n, 1, 2);
  LinearSolver s;
  ASSERT_TRUE(s.factorize(A, true, 1));
  EXPECT_EQ(s.stats().last_solver, "cholmod");
  EXPECT_LT((A * s.solve(b) - b).norm(), 1e-12);
  ASSERT_TRUE(s.factorize(A, true, 1));
  EXPECT_EQ(s.stats().analyses, 1);  // symbolic analysis reused
  SpMat N = A;
  N.coeffRef(0, 1) = -2.0;  // nonsymmetric
  ASSERT_TRUE(s.factorize(N, false, 1));
  EXPECT_EQ(s.stats().last_solver, "klu");
  EXPECT_LT((N * s.solve(b) - b).norm(), 1e-12);
  // Indefinite but symmetric: Cholesky fails, LU takes over.
  SpMat I = A;
  I.coeffRef(3, 3) = -4.0;
  ASSERT_TRUE(s.factorize(I, true, 1));
  EXPECT_EQ(s.stats().cholesky_fallbacks, 1);
  EXPECT_EQ(s.stats().by_cholmod, 3);  // A twice, then I (failed)
  EXPECT_EQ(s.stats().by_klu, 2);      // N, then I
  EXPECT_LT((I * s.solve(b) - b).norm(), 1e-10);
  // UMFPACK instead of KLU: the same solutions.
  LinearSolver u(LinearSolverChoice::Auto, CholeskyMode::Supernodal, LuMode::Umfpack);
  ASSERT_TRUE(u.factorize(N, false, 1));
  EXPECT_EQ(u.stats().last_solver, "umfpack");
  EXPECT_LT((N * u.solve(b) - b).norm(), 1e-12);
}

// What solve_reads_matrix() says: after the factorization, the matrix's
// values are overwritten (as a Newton trial's scatter would); CHOLMOD's and
// KLU's solves keep their bits, UMFPACK's refinement reads the new values.
TEST(LinearSolver, OnlyUmfpacksSolveReadsTheMatrixAfterItsFactorization) {
  const int n = 50;
  const Vec b = Vec::LinSpaced(n, 1, 2);
  struct Case {
    bool symmetric;
    LuMode lu;
    std::string solver;
  };
  for (const Case& c : {Case{true, LuMode::Auto, "cholmod"}, Case{false, LuMode::Klu, "klu"},
                        Case{false, LuMode::Umfpack, "umfpack"}}) {
    SpMat A = tridiagonal(n, -1.0, 4.0, c.symmetric ? -1.0 : -2.0);
    LinearSolver s(LinearSolverChoice::Auto, CholeskyMode::Supernodal, c.lu);
    ASSERT_TRUE(s.factorize(A, c.symmetric, 1));
    ASSERT_EQ(s.stats().last_solver, c.solver);
    const Vec x = s.solve(b);
    for (Eigen::Index k = 0; k < A.nonZeros(); ++k) A.valuePtr()[k] *= 1.5;
    const Vec y = s.solve(b);
    EXPECT_EQ(s.solve_reads_matrix(), c.solver == "umfpack") << c.solver;
    EXPECT_EQ((x - y).cwiseAbs().maxCoeff() > 0, s.solve_reads_matrix()) << c.solver;
  }
}

// solver.lu = auto: KLU below kKluMaxRows rows, UMFPACK from there, each
// solving a nonsymmetric tridiagonal system to round-off.
TEST(LinearSolver, AutoLuIsKluForSmallSystemsUmfpackForLarge) {
  for (const long n : {kKluMaxRows - 1, kKluMaxRows}) {
    const SpMat A = tridiagonal(n, -1.0, 4.0, -2.0);
    const Vec b = Vec::LinSpaced(n, 1, 2);
    LinearSolver s;
    ASSERT_TRUE(s.factorize(A, false, 1));
    EXPECT_EQ(s.stats().last_solver, n < kKluMaxRows ? "klu" : "umfpack") << n;
    EXPECT_EQ(s.stats().by_klu, n < kKluMaxRows ? 1 : 0) << n;
    EXPECT_EQ(s.stats().by_umfpack, n < kKluMaxRows ? 0 : 1) << n;
    EXPECT_EQ(s.stats().by_cholmod, 0) << n;
    EXPECT_LT((A * s.solve(b) - b).norm(), 1e-12 * b.norm()) << n;
  }
}

// CholmodLLT hands CHOLMOD tril(P A P^T) in the natural ordering, gathered
// from A, for a supernodal factor (a simplicial one takes CHOLMOD's own
// path): the solutions are what CHOLMOD computes from A with its own
// ordering (Eigen's wrapper, the same AMD and postorder), to the bit, for
// new values of the same pattern too; an indefinite matrix is refused as
// CHOLMOD refuses it, a matrix of another pattern as a logic error.
TEST(CholmodLLT, FactorizesTheMatrixInTheFactorsOrderAsCholmodDoes) {
  const int m = 40, n = 2 * m * m;  // two unknowns per node of a 40 x 40 grid
  const auto matrix = [&](double shift) {
    std::vector<Eigen::Triplet<double>> t;
    const auto couple = [&](int a, int b, double w) {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
          const double c = (i == j ? 1.0 : 0.3) * w;
          t.emplace_back(2 * a + i, 2 * a + j, c), t.emplace_back(2 * b + i, 2 * b + j, c);
          t.emplace_back(2 * a + i, 2 * b + j, -c), t.emplace_back(2 * b + j, 2 * a + i, -c);
        }
    };
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const int k = i * m + j;
        t.emplace_back(2 * k, 2 * k, shift), t.emplace_back(2 * k + 1, 2 * k + 1, shift);
        if (i > 0) couple(k, k - m, 1.0 + 0.01 * ((7 * k) % 13));
        if (j > 0) couple(k, k - 1, 1.0 + 0.01 * ((11 * k) % 17));
        if (i > 0 && j > 0) couple(k, k - m - 1, 0.5);
      }
    SpMat A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  const Vec b = Vec::LinSpaced(n, -1, 2);
  for (const bool super : {true, false}) {
    Eigen::CholmodDecomposition<SpMat, Eigen::Lower> ref;
    ref.setMode(super ? Eigen::CholmodSupernodalLLt : Eigen::CholmodSimplicialLLt);
    CholmodLLT llt(super ? CholmodLLT::Mode::Supernodal : CholmodLLT::Mode::Simplicial);
    set_kernel_options(ref.cholmod());
    const SpMat A = matrix(0.1);
    on_one_thread([&] { ref.analyzePattern(A); });
    llt.analyze(A);
    EXPECT_EQ(llt.supernodal(), super);
    for (const double shift : {0.1, 2.5}) {
      SCOPED_TRACE(testing::Message() << (super ? "supernodal" : "simplicial") << ", shift " << shift);
      const SpMat As = matrix(shift);
      on_one_thread([&] { ref.factorize(As); });
      ASSERT_EQ(ref.info(), Eigen::Success);
      ASSERT_TRUE(llt.factorize(As));
      Vec xr;
      on_one_thread([&] { xr = ref.solve(b); });
      const Vec x = llt.solve(b);
      EXPECT_LT((As * x - b).norm(), 1e-10 * b.norm());
      EXPECT_EQ(std::memcmp(x.data(), xr.data(), sizeof(double) * n), 0) << (x - xr).norm();
    }
    SpMat I = matrix(0.1);
    I.coeffRef(17, 17) = -1.0;
    EXPECT_FALSE(llt.factorize(I));
    // A matrix of another pattern is refused, not read through the
    // analyzed pattern's positions.
    SpMat J = matrix(0.1);
    J.coeffRef(0, n - 1) = J.coeffRef(n - 1, 0) = 1e-3;
    EXPECT_THROW(llt.factorize(J), std::logic_error);
  }
}

// CHOLMOD's supernodal factorization opens OpenMP loops of 4 threads
// (CHOLMOD_OMP_NUM_THREADS) where n > 128; LinearSolver runs it on one
// thread, so a factorization adds no thread to the process (OpenMP's pool
// would keep the three it started). The count is read from /proc.
TEST(LinearSolver, CholmodStartsNoThreads) {
  const auto threads = [] {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator("/proc/self/task")) n += e.is_directory();
    return n;
  };
  const int m = 30, n = m * m;  // a 30 x 30 grid's Laplacian plus a shift
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int k = i * m + j;
      t.emplace_back(k, k, 4.1);
      if (i > 0) t.emplace_back(k, k - m, -1.0), t.emplace_back(k - m, k, -1.0);
      if (j > 0) t.emplace_back(k, k - 1, -1.0), t.emplace_back(k - 1, k, -1.0);
    }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  const int before = threads();
  const std::uint64_t inlined = inline_openmp_regions();
  LinearSolver s(LinearSolverChoice::Cholmod, CholeskyMode::Supernodal);
  ASSERT_TRUE(s.factorize(A, true, 1));
  const Vec b = Vec::Ones(n);
  EXPECT_LT((A * s.solve(b) - b).norm(), 1e-10);
  EXPECT_EQ(threads(), before);
  // Its regions reached the program's GOMP_parallel and ran inline, no
  // team started for them (la/inline_openmp.hpp).
  EXPECT_GT(inline_openmp_regions(), inlined);
}

// Outside an InlineOpenMP scope a parallel region gets its team from
// libgomp, as ever; inside, the region runs on the calling thread alone.
TEST(InlineOpenMP, RegionsRunInlineOnlyInsideTheScope) {
#ifdef _OPENMP
  int team = 0;
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  EXPECT_EQ(team, 2);
  const std::uint64_t inlined = inline_openmp_regions();
  {
    const InlineOpenMP scope;
    int runs = 0;
#pragma omp parallel num_threads(2)
    {
      ++runs;  // a team of one: no race
      team = omp_get_num_threads();
    }
    EXPECT_EQ(runs, 1);
    EXPECT_EQ(team, 1);
  }
  EXPECT_EQ(inline_openmp_regions(), inlined + 1);
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    team = omp_get_num_threads();
  }
  EXPECT_EQ(team, 2);
#else
  // A check that cannot run fails unless the environment allows the skip
  // (docs/testing.md).
  const char* allow = std::getenv("RPFEM_ALLOW_SKIP");
  if (allow == nullptr || std::string(allow) != "1")
    FAIL() << "cannot run: built without OpenMP (RPFEM_ALLOW_SKIP=1 skips it)";
  GTEST_SKIP() << "built without OpenMP (RPFEM_ALLOW_SKIP=1)";
#endif
}

// KLU refactorizes a matrix of the pattern it factorized with the pivots
// it chose then, and factorizes in full again where those pivots would
// lose more than kRefactorRcondLoss of the pivot ratio: a matrix whose
// first diagonal entry drops by 1e6 (the kept pivot order would divide by
// it) is solved to round-off all the same.
TEST(KluLU, RefactorizesWithTheLastPivotsUnlessTheyDegrade) {
  const int n = 30;
  const SpMat A = tridiagonal(n, -1.0, 4.0, -1.5);
  const Vec b = Vec::LinSpaced(n, 1, 2);
  KluLU lu;
  lu.analyze(A);
  ASSERT_TRUE(lu.factorize(A));
  EXPECT_EQ(lu.full_factorizations(), 1);
  EXPECT_LT((A * lu.solve(b) - b).norm(), 1e-12);
  SpMat B = A;
  B.coeffRef(5, 5) = 5.0;  // values change, pivots still good
  ASSERT_TRUE(lu.factorize(B));
  EXPECT_EQ(lu.full_factorizations(), 1);
  EXPECT_EQ(lu.refactorizations(), 1);
  EXPECT_LT((B * lu.solve(b) - b).norm(), 1e-12);
  SpMat C = A;
  C.coeffRef(0, 0) = 4e-6;  // the first pivot nearly vanishes
  ASSERT_TRUE(lu.factorize(C));
  EXPECT_EQ(lu.full_factorizations(), 2);
  EXPECT_LT((C * lu.solve(b) - b).norm(), 1e-10 * b.norm());
  EXPECT_GT(lu.rcond(), 0.0);
}

// CHOLMOD's simplicial factorization (solver.cholesky) solves what the
// supernodal one does, with a condition estimate, and falls back to LU on
// an indefinite matrix the same way.
TEST(LinearSolver, SimplicialCholeskySolvesAsSupernodal) {
  const int n = 400;  // a 20 x 20 grid Laplacian plus a shift: SPD
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) {
      const int k = 20 * i + j;
      t.emplace_back(k, k, 4.5);
      if (i > 0) t.emplace_back(k, k - 20, -1.0), t.emplace_back(k - 20, k, -1.0);
      if (j > 0) t.emplace_back(k, k - 1, -1.0), t.emplace_back(k - 1, k, -1.0);
    }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  const Vec b = Vec::LinSpaced(n, -1, 2);
  LinearSolver super(LinearSolverChoice::Auto, CholeskyMode::Supernodal);
  LinearSolver simple(LinearSolverChoice::Auto, CholeskyMode::Simplicial);
  LinearSolver chosen(LinearSolverChoice::Auto, CholeskyMode::Auto);
  ASSERT_TRUE(super.factorize(A, true, 1));
  ASSERT_TRUE(simple.factorize(A, true, 1));
  ASSERT_TRUE(chosen.factorize(A, true, 1));
  EXPECT_LT((chosen.solve(b) - super.solve(b)).norm(), 1e-13 * b.norm());
  EXPECT_EQ(simple.stats().last_solver, "cholmod");
  const Vec x1 = super.solve(b), x2 = simple.solve(b);
  EXPECT_LT((A * x2 - b).norm(), 1e-12 * b.norm());
  EXPECT_LT((x1 - x2).norm(), 1e-13 * x1.norm());
  EXPECT_NEAR(simple.stats().last_rcond, super.stats().last_rcond, 1e-12);
  EXPECT_GT(simple.stats().last_rcond, 0.0);
  SpMat I = A;
  I.coeffRef(7, 7) = -4.0;
  ASSERT_TRUE(simple.factorize(I, true, 1));
  EXPECT_EQ(simple.stats().cholesky_fallbacks, 1);
  EXPECT_LT((I * simple.solve(b) - b).norm(), 1e-10 * b.norm());
}

// Pi(u) = sum sqrt(1 + u_i^2) - c.u: residual, consistent tangent and
// secant matrix S(u) u = R + c (S = 1 / sqrt(1 + u^2), as sigma / epsdot).
struct SqrtProblem {
  Vec c;
  std::vector<int> kinds;  // 1 consistent, 0 secant, per solve
  NewtonSystem system() {
    NewtonSystem sys;
    sys.energy = [this](const Vec& u) { return (1 + u.array().square()).sqrt().sum() - c.dot(u); };
    sys.residual = [this](const Vec& u, Vec& R, double& s) {
      R = (u.array() / (1 + u.array().square()).sqrt()).matrix() - c;
      s = c.norm();
    };
    sys.solve = [this](const Vec& u, bool consistent, const Vec& R, Vec& du) {
      kinds.push_back(consistent);
      const Eigen::ArrayXd w = (1 + u.array().square()).sqrt();
      const Eigen::ArrayXd d = consistent ? Eigen::ArrayXd(w.pow(3)) : w;
      du = (-R.array() * d).matrix();
      return true;
    };
    return sys;
  }
  double error(const Vec& u) const {
    return (u - (c.array() / (1 - c.array().square()).sqrt()).matrix()).norm() / u.norm();
  }
};

TEST(Newton, ConvergesQuadraticallyFromAPoorStart) {
  // Convex, minimizer u_i = c_i/sqrt(1-c_i^2); plain Newton diverges from u = 30.
  SqrtProblem p;
  p.c = Vec(4);
  p.c << 0.3, -0.5, 0.9, 0.1;
  Vec u = Vec::Constant(4, 30.0);
  NewtonSettings s;
  s.direct_iterations = 0;
  s.tol_velocity = 1e-12;
  s.tol_force = 1e-12;
  const NewtonResult r = newton_solve(p.system(), s, u);
  ASSERT_TRUE(r.converged) << r.reason;
  EXPECT_GT(r.halvings, 0);
  EXPECT_LE(r.iterations, 30);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(u(i), p.c(i) / std::sqrt(1 - p.c(i) * p.c(i)), 1e-10);
}

// The error left in u is estimated from the contraction of two full Newton
// steps: the solve stops once that estimate meets tol_velocity, before the
// last correction itself does, and the error is indeed below it.
TEST(Newton, StopsWhenTheEstimatedErrorMeetsTheTolerance) {
  SqrtProblem p;
  p.c = Vec(3);
  p.c << 0.3, -0.5, 0.6;
  Vec u = Vec::Constant(3, 0.5);  // corrections 1.2, 0.31, 0.048, 1.5e-3, 1.4e-6, 1.3e-12
  NewtonSettings s;
  s.direct_iterations = 0;
  s.tol_velocity = 1e-8;
  s.tol_force = 1.0;  // the velocity criterion decides
  const NewtonResult r = newton_solve(p.system(), s, u);
  ASSERT_TRUE(r.converged) << r.reason;
  EXPECT_EQ(r.halvings, 0);
  EXPECT_GT(r.correction, s.tol_velocity);  // the plain criterion would iterate on
  EXPECT_LT(p.error(u), s.tol_velocity);
}

// After a line search cut the step, the next iteration is a secant one;
// from a start where Newton overshoots this converges in fewer iterations.
TEST(Newton, TakesASecantIterationAfterACutLineSearch) {
  const auto run = [](bool secant_after_cut, SqrtProblem& p) {
    p.c = Vec(4);
    p.c << 0.3, -0.5, 0.9, 0.1;
    Vec u = Vec::Constant(4, 30.0);
    NewtonSettings s;
    s.direct_iterations = 0;
    s.secant_after_cut = secant_after_cut;
    s.tol_velocity = s.tol_force = 1e-12;
    const NewtonResult r = newton_solve(p.system(), s, u);
    EXPECT_TRUE(r.converged) << r.reason;
    EXPECT_LT(p.error(u), 1e-10);
    return r;
  };
  SqrtProblem with, without;
  const NewtonResult a = run(true, with), b = run(false, without);
  EXPECT_EQ(std::count(without.kinds.begin(), without.kinds.end(), 0), 0);
  EXPECT_GT(std::count(with.kinds.begin(), with.kinds.end(), 0), 0);
  EXPECT_EQ(with.kinds.front(), 1);  // the first iteration is Newton's
  EXPECT_LT(a.iterations, b.iterations);
  std::printf("[measured] from u = 30: %d iterations with a secant step after each cut, %d without\n", a.iterations,
              b.iterations);
}

// A re-solve after a small change of the right-hand side (c moved by 1e-3)
// starts with the held factorization (the chord method): it converges to
// the same tolerance with fewer fresh tangents than Newton, and its error
// estimate theta / (1 - theta) |du| is honest.
TEST(Newton, ReusesTheHeldFactorizationForASmallChange) {
  SqrtProblem p;
  p.c = Vec(3);
  p.c << 0.3, -0.5, 0.6;
  NewtonSettings s;
  s.direct_iterations = 0;
  s.tol_velocity = 1e-10;
  s.tol_force = 1.0;
  Vec u0 = Vec::Zero(3);
  ASSERT_TRUE(newton_solve(p.system(), s, u0).converged);
  // The factorization held: the consistent tangent's inverse at u0.
  const Eigen::ArrayXd held = (1 + u0.array().square()).sqrt().pow(3);
  int reused = 0;
  NewtonSystem sys = p.system();
  sys.reuse = [&](const Vec& R, Vec& du) {
    ++reused;
    du = (-R.array() * held).matrix();
    return true;
  };
  p.c(2) += 1e-3;
  Vec chord = u0, newton = u0;
  p.kinds.clear();
  s.reuse_factorization = true;
  const NewtonResult a = newton_solve(sys, s, chord);
  const std::size_t fresh_chord = p.kinds.size();
  p.kinds.clear();
  s.reuse_factorization = false;
  const NewtonResult b = newton_solve(p.system(), s, newton);
  const std::size_t fresh_newton = p.kinds.size();
  ASSERT_TRUE(a.converged) << a.reason;
  ASSERT_TRUE(b.converged) << b.reason;
  EXPECT_GE(reused, 2);
  EXPECT_LT(fresh_chord, fresh_newton);
  EXPECT_LT(p.error(chord), s.tol_velocity);
  EXPECT_LT(p.error(newton), s.tol_velocity);
  // Without a held factorization the solve is Newton's.
  sys.reuse = [](const Vec&, Vec&) { return false; };
  Vec none = u0;
  p.kinds.clear();
  s.reuse_factorization = true;
  ASSERT_TRUE(newton_solve(sys, s, none).converged);
  std::printf("[measured] after a change of 1e-3: %zu fresh tangents and %d held with the chord method, %zu by Newton\n",
              fresh_chord, reused, fresh_newton);
  EXPECT_EQ(p.kinds.size(), fresh_newton);
  EXPECT_LT(p.error(none), s.tol_velocity);
}

TEST(Newton, ReportsNonFiniteResidual) {
  NewtonSystem sys;
  sys.residual = [](const Vec& u, Vec& R, double& s) {
    R = Vec::Constant(1, std::nan(""));
    s = 1;
  };
  sys.solve = [](const Vec&, bool, const Vec&, Vec& du) {
    du = Vec::Ones(1);
    return true;
  };
  Vec u = Vec::Zero(1);
  const NewtonResult r = newton_solve(sys, NewtonSettings{}, u);
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.reason.empty());
}

// A residual with a floor Newton cannot remove (the round-off of terms far
// larger than the forces, as a virtual rigid body's): the solve stops on
// the floor when it is near tol_force, and fails when it is far above.
TEST(Newton, StopsOnTheRoundOffFloorOnlyNearTheTolerance) {
  const auto run = [](double floor) {
    NewtonSystem sys;
    // R = (u - 1) + floor, scale 1; the solve ignores the floor, as a
    // factorization does with round-off it cannot see.
    sys.residual = [floor](const Vec& u, Vec& R, double& s) {
      R = (u.array() - 1.0).matrix() + Vec::Constant(u.size(), floor);
      s = 1;
    };
    sys.solve = [](const Vec& u, bool, const Vec&, Vec& du) {
      du = (1.0 - u.array()).matrix();
      return true;
    };
    Vec u = Vec::Zero(2);
    NewtonSettings s;
    s.max_iterations = 10;
    return newton_solve(sys, s, u);
  };
  const NewtonResult near = run(2e-6);  // 20 x tol_force (1e-7)
  EXPECT_TRUE(near.converged) << near.reason;
  EXPECT_TRUE(near.at_round_off);
  EXPECT_GT(near.residual, 1e-7);
  EXPECT_FALSE(near.stalled);
  const NewtonResult far = run(1e-4);
  EXPECT_FALSE(far.converged);
  // Far above: stalled at the floor, and the reason says so (the stepper
  // then reports the tangent as ill-conditioned).
  EXPECT_TRUE(far.stalled);
  EXPECT_NE(far.reason.find("stalled at the residual's round-off floor"), std::string::npos) << far.reason;
  const NewtonResult none = run(0);
  EXPECT_TRUE(none.converged);
  EXPECT_FALSE(none.at_round_off);
  EXPECT_FALSE(none.stalled);
}

// A failure that is not at the floor (the corrections stay large) is not
// reported as stalled.
TEST(Newton, DivergenceIsNotAStall) {
  NewtonSystem sys;
  sys.residual = [](const Vec& u, Vec& R, double& s) {
    R = Vec::Constant(1, 1.0 + 1e-3 * u(0));  // never zero along the corrections below
    s = 1;
  };
  sys.solve = [](const Vec&, bool, const Vec&, Vec& du) {
    du = Vec::Constant(1, 0.5);
    return true;
  };
  Vec u = Vec::Ones(1);
  NewtonSettings s;
  s.max_iterations = 5;
  const NewtonResult r = newton_solve(sys, s, u);
  EXPECT_FALSE(r.converged);
  EXPECT_FALSE(r.stalled);
  EXPECT_EQ(r.reason.find("stalled"), std::string::npos) << r.reason;
}

// The condition estimate of a diagonal matrix diag(1, ..., 1, 1e-6) is its
// exact reciprocal condition number, 1e-6, from either factorization
// (CHOLMOD returns the square of L's diagonal ratio, L_ii = sqrt(a_ii));
// the least since reset_rcond() is kept.
TEST(LinearSolver, ConditionEstimateFromTheFactorDiagonal) {
  const int n = 10;
  SpMat D(n, n);
  for (int i = 0; i < n; ++i) D.insert(i, i) = i == n - 1 ? 1e-6 : 1.0;
  SpMat W = D;
  W.coeffRef(n - 1, n - 1) = 1e-12;
  LinearSolver chol;
  ASSERT_TRUE(chol.factorize(D, true, 1));
  EXPECT_NEAR(chol.stats().last_rcond, 1e-6, 1e-18);
  for (LuMode mode : {LuMode::Klu, LuMode::Umfpack}) {
    LinearSolver lu(LinearSolverChoice::Lu, CholeskyMode::Supernodal, mode);
    ASSERT_TRUE(lu.factorize(D, true, 1));
    EXPECT_NEAR(lu.stats().last_rcond, 1e-6, 1e-18);
    ASSERT_TRUE(lu.factorize(W, true, 1));
    ASSERT_TRUE(lu.factorize(D, true, 1));
    EXPECT_NEAR(lu.stats().min_rcond, 1e-12, 1e-24);
    lu.reset_rcond();
    EXPECT_TRUE(std::isinf(lu.stats().min_rcond));
  }
}

// A singular matrix: both factorizations fail, and the condition estimate
// of the step records 0 (a failed solve then reports an ill-conditioned
// tangent, not the estimate of an earlier matrix).
TEST(LinearSolver, SingularMatrixRecordsZeroCondition) {
  SpMat A(2, 2);
  A.insert(0, 0) = 1.0, A.insert(0, 1) = 1.0, A.insert(1, 0) = 1.0, A.insert(1, 1) = 1.0;
  SpMat I(2, 2);
  I.insert(0, 0) = 1.0, I.insert(1, 1) = 1.0;
  for (auto [choice, mode] : {std::pair{LinearSolverChoice::Auto, LuMode::Klu}, std::pair{LinearSolverChoice::Cholmod, LuMode::Klu},
                               std::pair{LinearSolverChoice::Lu, LuMode::Klu}, std::pair{LinearSolverChoice::Lu, LuMode::Umfpack}}) {
    LinearSolver s(choice, CholeskyMode::Supernodal, mode);
    ASSERT_TRUE(s.factorize(I, true, 1));
    EXPECT_EQ(s.stats().min_rcond, 1.0);
    EXPECT_FALSE(s.factorize(A, true, 2));
    EXPECT_EQ(s.stats().min_rcond, 0.0);
  }
}
