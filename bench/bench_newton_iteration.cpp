// Cost of one Newton iteration of the kernel against the bare sparse direct
// solve, for meshes of about 1e3, 1e4 and 1e5 unknowns.
//
//   build/bench/rpfem_bench --benchmark_counters_tabular=true
//
// BM_Assembly: residual + consistent tangent, on the threads given by the
// second argument (model/element_loop.hpp). BM_FactorSolve: the kernel's
// CHOLMOD numeric factorization + solve of the same matrix (symbolic
// analysis reused, as in the runs; la/cholmod_llt.hpp). BM_NewtonIteration: what newton_solve does per
// iteration: one line-search trial (residual and energy, with the
// consistent tangent's element terms kept, from one element pass: the
// trial accepted, it is the next iterate), the tangent scattered from those
// terms (on one element thread, within that pass), factorization and
// solve. BM_NewtonIterationTwoPasses: the same
// with the tangent's own element pass (as a trial that is not taken, or
// before StepProblem::keep_tangent_terms). BM_NewtonIterationRatio: the
// iteration against the bare CHOLMOD factorization and solve and against
// the kernel's own, side by side.
// BM_Cholmod*: CHOLMOD's
// supernodal and simplicial factorizations; BM_Umfpack, BM_Klu*: the LU
// factorizations. Counter peak_rss_MB: the process's peak memory.
#include <Eigen/CholmodSupport>
#include <Eigen/KLUSupport>
#include <Eigen/UmfPackSupport>
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/linked_blas.hpp"
#include "la/cholmod_llt.hpp"
#include "la/inline_openmp.hpp"
#include "la/klu_lu.hpp"
#include "mesh/generate.hpp"
#include "model/step_problem.hpp"
#include "none/no_contact.hpp"

using namespace rpfem;

namespace {

struct Fixture {
  Mesh mesh;
  FlowStressLaw law{900.0, 0.17, 0.02, 0.0, 1.0};
  std::vector<ElementMaterial> mats;
  std::vector<std::array<double, 4>> strain;
  std::vector<double> flow;
  std::vector<Vec2> fext;
  StepView view;
  NoContact none;
  SolverWorkspace ws{LinearSolverChoice::Auto};
  std::unique_ptr<StepProblem> problem;
  Vec u;

  explicit Fixture(int n) {
    RectangleSpec s;
    s.width = 10;
    s.height = 10;
    s.nx = s.ny = n;
    mesh = make_rectangle("b", s);
    mats.assign(mesh.num_elements(), ElementMaterial{&law, 1e5 * 900.0 / 0.1});
    strain.assign(mesh.num_elements(), {0.1, 0.1, 0.1, 0.1});
    flow.assign(mesh.num_elements(), 900.0);
    fext.assign(mesh.x.size(), Vec2::Zero());
    view.mesh = &mesh;
    view.x = &mesh.x;
    view.flow_stress = &flow;
    view.geometry = Geometry::Axisymmetric;
    problem = std::make_unique<StepProblem>(view, strain, mats, 1e-4, fext, none, ws);
    std::vector<NodeConstraint> cons;
    for (Index i : mesh.side_nodes("b.top")) cons.push_back({i, Vec2(0, 1), -1.0});
    for (Index i : mesh.side_nodes("b.bottom")) cons.push_back({i, Vec2(0, 1), 0.0});
    for (Index i : mesh.side_nodes("b.left")) cons.push_back({i, Vec2(1, 0), 0.0});
    problem->set_constraints(cons);
    // A non-uniform field, so every element has its own state.
    std::vector<Vec2> v(mesh.x.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Vec2& x = mesh.x[i];
      v[i] = Vec2(0.05 * x(0) * (1 + 0.1 * std::sin(x(1))), -0.1 * x(1));
    }
    u = problem->dofs().reduce(v);
    const SpMat& A = problem->tangent(u, true);
    ws.linear.factorize(A, true, ws.assembler.pattern_version());  // symbolic analysis once
  }
};

Fixture& fixture(int n) {
  static std::map<int, std::unique_ptr<Fixture>> cache;
  auto& f = cache[n];
  if (!f) f = std::make_unique<Fixture>(n);
  return *f;
}

void counters(benchmark::State& state, const Fixture& f) {
  rusage r;
  getrusage(RUSAGE_SELF, &r);
  state.counters["unknowns"] = static_cast<double>(f.u.size());
  state.counters["nnz"] = static_cast<double>(f.ws.assembler.matrix().nonZeros());
  state.counters["peak_rss_MB"] = r.ru_maxrss / 1024.0;
}

void BM_Assembly(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  f.ws.threads = static_cast<int>(state.range(1));
  Vec R;
  double scale;
  for (auto _ : state) {
    f.problem->residual(f.u, R, scale);
    benchmark::DoNotOptimize(f.problem->tangent(f.u, true).nonZeros());
  }
  counters(state, f);
  state.counters["threads"] = f.ws.threads;
  f.ws.threads = 1;
}

// The parts of a Newton iteration beyond the factorization, one by one:
// 0 the tangent alone, 1 the residual, 2 the energy (the line search's).
void BM_Part(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  const int part = static_cast<int>(state.range(1));
  Vec R;
  double scale;
  for (auto _ : state) {
    if (part == 0) benchmark::DoNotOptimize(f.problem->tangent(f.u, true).nonZeros());
    if (part == 1) f.problem->residual(f.u, R, scale), benchmark::DoNotOptimize(R.data());
    if (part == 2) benchmark::DoNotOptimize(f.problem->energy(f.u));
  }
  counters(state, f);
  state.SetLabel(part == 0 ? "tangent" : part == 1 ? "residual" : "energy");
}

// The bare factorization and solve of A (symbolic analysis reused).
void factor_solve(Fixture& f, const SpMat& A, const Vec& b) {
  f.ws.linear.factorize(A, true, f.ws.assembler.pattern_version());
  benchmark::DoNotOptimize(f.ws.linear.solve(b).data());
}

// One Newton iteration as newton_solve does it after an accepted full
// step: the trial's element pass (residual and energy, the consistent
// tangent's terms kept; on one thread scattered as they are formed), the
// tangent from them, factorization and solve.
void newton_iteration(Fixture& f, Vec& R, Vec& du) {
  double scale;
  f.problem->keep_tangent_terms(true);
  benchmark::DoNotOptimize(f.problem->residual_energy(f.u, R, scale));
  f.problem->keep_tangent_terms(false);
  f.problem->solve(f.u, true, R, du);
  benchmark::DoNotOptimize(du.data());
}

void BM_FactorSolve(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  const SpMat& A = f.problem->tangent(f.u, true);
  const Vec b = Vec::Ones(f.u.size());
  for (auto _ : state) factor_solve(f, A, b);
  counters(state, f);
}

void BM_NewtonIteration(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  f.ws.threads = static_cast<int>(state.range(1));
  Vec R, du;
  for (auto _ : state) newton_iteration(f, R, du);
  counters(state, f);
  state.counters["threads"] = f.ws.threads;
  f.ws.threads = 1;
}

void BM_NewtonIterationTwoPasses(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  f.ws.threads = static_cast<int>(state.range(1));
  Vec R, du;
  double scale;
  f.problem->residual(f.u, R, scale);
  for (auto _ : state) {
    f.problem->solve(f.u, true, R, du);
    const Vec trial = f.u + du;
    benchmark::DoNotOptimize(f.problem->residual_energy(trial, R, scale));
  }
  counters(state, f);
  state.counters["threads"] = f.ws.threads;
  f.ws.threads = 1;
}

// The ratio of the two above, measured interleaved: each benchmark
// iteration times the bare CHOLMOD factorization and solve of the tangent
// (Eigen's CholmodSupernodalLLT with the kernel's settings: AMD ordering,
// postordered, symbolic analysis reused, on one thread with its OpenMP
// regions inline), the kernel's own factorization and solve of it
// (la/cholmod_llt.hpp: the same CHOLMOD factor, from the matrix gathered
// into the factor's order), then one Newton iteration (as
// BM_NewtonIteration). Counters: the medians of each (`cholmod_ms`,
// `factor_solve_ms`, `iteration_ms`) and of the per-pair ratios, `ratio`
// the iteration over bare CHOLMOD, `ratio_to_solver` over the kernel's
// factorization. Series of the benchmarks minutes apart moved by 10 % on
// this machine, more than the difference sought; side by side, a pair
// sees the same machine.
void BM_NewtonIterationRatio(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  f.ws.threads = static_cast<int>(state.range(1));
  Vec R, du;
  const Vec b = Vec::Ones(f.u.size());
  const SpMat& A0 = f.problem->tangent(f.u, true);
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> cholmod;
  set_kernel_options(cholmod.cholmod());
  on_one_thread([&] { cholmod.analyzePattern(A0); });
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point z) {
    return std::chrono::duration<double, std::milli>(z - a).count();
  };
  std::vector<double> bare, solver, iteration, ratio, ratio_solver;
  for (auto _ : state) {
    const SpMat& A = f.problem->tangent(f.u, true);
    const auto t0 = Clock::now();
    on_one_thread([&] {
      cholmod.factorize(A);
      benchmark::DoNotOptimize(Vec(cholmod.solve(b)).data());
    });
    const auto t1 = Clock::now();
    factor_solve(f, A, b);
    const auto t2 = Clock::now();
    newton_iteration(f, R, du);
    const auto t3 = Clock::now();
    bare.push_back(ms(t0, t1)), solver.push_back(ms(t1, t2)), iteration.push_back(ms(t2, t3));
    ratio.push_back(iteration.back() / bare.back()), ratio_solver.push_back(iteration.back() / solver.back());
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  counters(state, f);
  state.counters["threads"] = f.ws.threads;
  state.counters["cholmod_ms"] = median(bare);
  state.counters["factor_solve_ms"] = median(solver);
  state.counters["iteration_ms"] = median(iteration);
  state.counters["ratio"] = median(ratio);
  state.counters["ratio_to_solver"] = median(ratio_solver);
  f.ws.threads = 1;
}

// A factorization of the bench's tangent, symbolic analysis reused:
// numeric factorization + solve per iteration, on one thread with its
// OpenMP regions inline where one_thread (on_one_thread, as
// la/linear_solver.cpp runs CHOLMOD). CHOLMOD's supernodal (the kernel's) and simplicial (no BLAS)
// factorizations, and the supernodal one as CHOLMOD opens its OpenMP loops
// (4 threads); UMFPACK (multifrontal, dense fronts through the BLAS)
// against KLU (left-looking, no BLAS; a full factorization with its pivot
// search each time). UMFPACK's symmetric strategy
// (UMFPACK_STRATEGY_SYMMETRIC) measured the same as its default on these
// tangents.
template <class Factor, bool one_thread = false>
void factor_solve(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  const SpMat& A = f.problem->tangent(f.u, true);
  const Vec b = Vec::Ones(f.u.size());
  Factor factor;
  if constexpr (requires { factor.cholmod(); }) factor.cholmod().print = 0;
  factor.analyzePattern(A);
  for (auto _ : state) {
    if constexpr (one_thread) {
      on_one_thread([&] { factor.factorize(A); });
    } else {
      factor.factorize(A);
    }
    benchmark::DoNotOptimize(Vec(factor.solve(b)).data());
  }
  counters(state, f);
}
using Supernodal = Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower>;
using Simplicial = Eigen::CholmodSimplicialLLT<SpMat, Eigen::Lower>;
void BM_CholmodSupernodal(benchmark::State& state) { factor_solve<Supernodal, true>(state); }
void BM_CholmodSimplicial(benchmark::State& state) { factor_solve<Simplicial, true>(state); }
void BM_CholmodSupernodalFourThreads(benchmark::State& state) { factor_solve<Supernodal>(state); }
void BM_Umfpack(benchmark::State& state) { factor_solve<Eigen::UmfPackLU<SpMat>>(state); }
void BM_Klu(benchmark::State& state) { factor_solve<Eigen::KLU<SpMat>>(state); }
// KLU as the kernel runs it (la/klu_lu.hpp): refactorizing with the pivots
// of its first factorization, each solve refined.
void BM_KluRefactor(benchmark::State& state) {
  Fixture& f = fixture(static_cast<int>(state.range(0)));
  const SpMat& A = f.problem->tangent(f.u, true);
  const Vec b = Vec::Ones(f.u.size());
  KluLU lu;
  lu.analyze(A);
  for (auto _ : state) {
    lu.factorize(A);
    benchmark::DoNotOptimize(lu.solve(b).data());
  }
  counters(state, f);
  state.counters["full_factorizations"] = lu.full_factorizations();
}

// n x n elements: 2 (n+1)^2 - constraints ~ 1e3, 1e4, 1e5 unknowns.
#define SIZES ->Arg(22)->Arg(70)->Arg(223)->Unit(benchmark::kMillisecond)
// The same with one and two threads of the element loops.
#define SIZES_THREADS ->ArgsProduct({{22, 70, 223}, {1, 2}})->Unit(benchmark::kMillisecond)
BENCHMARK(BM_Assembly) SIZES_THREADS;
BENCHMARK(BM_Part)->ArgsProduct({{22, 70, 223}, {0, 1, 2}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorSolve) SIZES;
BENCHMARK(BM_NewtonIteration) SIZES_THREADS;
BENCHMARK(BM_NewtonIterationTwoPasses) SIZES_THREADS;
BENCHMARK(BM_NewtonIterationRatio) SIZES_THREADS;
BENCHMARK(BM_CholmodSupernodal)->Arg(22)->Arg(40)->Arg(70)->Arg(223)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CholmodSimplicial)->Arg(22)->Arg(40)->Arg(70)->Arg(223)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CholmodSupernodalFourThreads)->Arg(22)->Arg(40)->Arg(70)->Arg(223)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Umfpack)->Arg(22)->Arg(40)->Arg(70)->Arg(120)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Klu)->Arg(22)->Arg(40)->Arg(70)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KluRefactor)->Arg(22)->Arg(40)->Arg(70)->Arg(120)->Unit(benchmark::kMillisecond);

}  // namespace

// The BLAS held to one thread, as `rpfem run` holds it by default
// (solver.blas_threads): left at OpenBLAS's default, its threads and the
// element loop's share the cores (the ratio at 1e5 unknowns read 1.29
// instead of 1.25 on one element thread; docs/benchmarks.md). The library
// and its thread count go into the report's context.
int main(int argc, char** argv) {
  const int blas_threads = rpfem::set_blas_threads(1);
  benchmark::AddCustomContext("blas", rpfem::linked_blas());
  benchmark::AddCustomContext("blas_threads", std::to_string(blas_threads));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
