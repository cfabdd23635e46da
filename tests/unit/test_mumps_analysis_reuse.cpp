// MUMPS's analysis reused across the solves of one pattern
// (formulations/ipopt/mumps_analysis_reuse.hpp): an analysis is answered
// from the instance's last one only when every input of it is the same,
// and the factorization on the reused analysis solves the system.
#include <dmumps_c.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ipopt/mumps_analysis_reuse.hpp"

using namespace rpfem;

namespace {

// A symmetric saddle-point system as Ipopt hands it to MUMPS (lower
// triangle, 1-based triplets): a 1D Laplacian over n unknowns and one
// constraint row coupling the first and last unknowns.
struct Kkt {
  int n;
  std::vector<MUMPS_INT> irn, jcn;
  std::vector<double> a;
  explicit Kkt(int n_) : n(n_) {
    for (int i = 1; i <= n; ++i) {
      add(i, i, 2.0 + 0.1 * i);
      if (i > 1) add(i, i - 1, -1.0);
    }
    add(n + 1, 1, 1.0);
    add(n + 1, n, -1.0);
  }
  void add(int i, int j, double v) { irn.push_back(i), jcn.push_back(j), a.push_back(v); }
  int order() const { return n + 1; }
};

class Mumps {
 public:
  Mumps() {
    id_.job = -1, id_.par = 1, id_.sym = 2, id_.comm_fortran = -987654;  // USE_COMM_WORLD
    dmumps_c(&id_);
    id_.icntl[0] = id_.icntl[1] = id_.icntl[2] = id_.icntl[3] = 0;  // silent
    id_.icntl[5] = 0;  // ICNTL(6): no maximum transversal
    id_.icntl[7] = 0;  // ICNTL(8): no scaling (so the analysis reads the pattern alone)
  }
  ~Mumps() {
    id_.job = -2;
    dmumps_c(&id_);
  }
  void set(Kkt& k) {
    id_.n = k.order();
    id_.nz = static_cast<MUMPS_INT>(k.a.size());
    id_.nnz = 0;
    id_.irn = k.irn.data(), id_.jcn = k.jcn.data(), id_.a = k.a.data();
  }
  int run(int job) {
    id_.job = job;
    dmumps_c(&id_);
    return id_.info[0];
  }
  // Factor and solve K x = b (b overwritten by x).
  std::vector<double> solve(std::vector<double> b) {
    EXPECT_EQ(run(2), 0);
    id_.rhs = b.data(), id_.nrhs = 1, id_.lrhs = id_.n;
    EXPECT_EQ(run(3), 0);
    return b;
  }
  DMUMPS_STRUC_C& id() { return id_; }

 private:
  DMUMPS_STRUC_C id_{};
};

// |K x - b| over the lower-triangle triplets.
double residual(const Kkt& k, const std::vector<double>& x, const std::vector<double>& b) {
  std::vector<double> r(b.size());
  for (std::size_t e = 0; e < k.a.size(); ++e) {
    const int i = k.irn[e] - 1, j = k.jcn[e] - 1;
    r[i] += k.a[e] * x[j];
    if (i != j) r[j] += k.a[e] * x[i];
  }
  double s = 0;
  for (std::size_t i = 0; i < b.size(); ++i) s += (r[i] - b[i]) * (r[i] - b[i]);
  return std::sqrt(s);
}

}  // namespace

TEST(MumpsAnalysisReuse, TheSamePatternIsAnalysedOnceAndStillSolved) {
  Kkt k(40);
  std::vector<double> b(k.order());
  for (int i = 0; i < k.order(); ++i) b[i] = std::sin(0.3 * i);
  Mumps m;
  m.set(k);
  const MumpsAnalysisCounts c0 = mumps_analysis_counts();
  ASSERT_EQ(m.run(1), 0);
  const auto x1 = m.solve(b);
  EXPECT_LT(residual(k, x1, b), 1e-12);
  // The same inputs again (new values, as a later Ipopt solve's): answered
  // from the last analysis, and the new matrix is solved on it.
  for (double& v : k.a) v *= 1.5;
  m.id().info[0] = -99;  // the reused analysis reports its own INFO(1)
  ASSERT_EQ(m.run(1), 0);
  const MumpsAnalysisCounts c1 = mumps_analysis_counts();
  EXPECT_EQ(c1.analysed - c0.analysed, 1);
  EXPECT_EQ(c1.reused - c0.reused, 1);
  const auto x2 = m.solve(b);
  EXPECT_LT(residual(k, x2, b), 1e-12);
  for (int i = 0; i < k.order(); ++i) EXPECT_NEAR(x2[i], x1[i] / 1.5, 1e-12);
}

TEST(MumpsAnalysisReuse, AnyChangedInputIsAnalysedAgain) {
  Kkt k(30);
  std::vector<double> b(k.order(), 1.0);
  Mumps m;
  m.set(k);
  ASSERT_EQ(m.run(1), 0);
  const auto analysed = [] { return mumps_analysis_counts().analysed; };
  long n = analysed();
  // A control parameter the analysis reads (ICNTL(7), the ordering).
  m.id().icntl[6] = m.id().icntl[6] == 0 ? 2 : 0;
  ASSERT_EQ(m.run(1), 0);
  EXPECT_EQ(analysed(), ++n);
  // A changed pattern of the same size: one column index moved.
  Kkt moved = k;
  moved.jcn[moved.jcn.size() - 1] = 2;
  m.set(moved);
  ASSERT_EQ(m.run(1), 0);
  EXPECT_EQ(analysed(), ++n);
  EXPECT_LT(residual(moved, m.solve(b), b), 1e-12);
  // One more entry.
  Kkt more = k;
  more.add(k.order(), 5, 0.5);
  m.set(more);
  ASSERT_EQ(m.run(1), 0);
  EXPECT_EQ(analysed(), ++n);
  EXPECT_LT(residual(more, m.solve(b), b), 1e-12);
  // Reuse switched off: the same inputs are analysed again.
  const bool was = set_mumps_analysis_reuse(false);
  ASSERT_EQ(m.run(1), 0);
  EXPECT_EQ(analysed(), ++n);
  set_mumps_analysis_reuse(was);
  ASSERT_EQ(m.run(1), 0);
  EXPECT_EQ(analysed(), n);
  // An analysis that reads the values (a maximum transversal, ICNTL(6) = 7;
  // scaling, ICNTL(8) = 77) is run every time, the same inputs or not.
  for (int k : {5, 7}) {
    const MUMPS_INT keep = m.id().icntl[k];
    m.id().icntl[k] = 7 * (k == 5) + 77 * (k == 7);
    ASSERT_EQ(m.run(1), 0);
    ASSERT_EQ(m.run(1), 0);
    EXPECT_EQ(analysed(), n += 2) << "icntl[" << k << "]";
    EXPECT_LT(residual(more, m.solve(b), b), 1e-12);
    m.id().icntl[k] = keep;
  }
}

TEST(MumpsAnalysisReuse, ANewInstanceIsAnalysedEvenAtTheSameAddress) {
  Kkt k(20);
  std::vector<double> b(k.order(), 1.0);
  const auto analysed = [] { return mumps_analysis_counts().analysed; };
  long n = analysed();
  {
    Mumps m;
    m.set(k);
    ASSERT_EQ(m.run(1), 0);
  }
  Mumps again;  // the stack slot of the first, likely
  again.set(k);
  ASSERT_EQ(again.run(1), 0);
  EXPECT_EQ(analysed(), n + 2);
  EXPECT_LT(residual(k, again.solve(b), b), 1e-12);
}
