// The penalty formulation's pair term (src/contact/row_terms.*,
// paper eq. 7-12): gradient and Hessian, including Coulomb friction's
// unsymmetric consistent tangent, against finite differences; action equals
// reaction; Hallquist's rule for the slave side.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/row_terms.hpp"
#include "dense_row_term.hpp"
#include "node_to_segment/roles.hpp"

using namespace rpfem;

namespace {

PairKinematics body_pair() {
  PairKinematics k;
  k.k = 3;
  k.nodes = {0, 1, 2};
  k.c = {1.0, -0.7, -0.3};
  k.n = Vec2(0.3, 1.0).normalized();
  k.gap0 = k.gap_from = -2e-4;
  return k;
}

RowLaw law(FrictionLaw::Kind kind) {
  RowLaw l;
  l.beta = 5e3;
  l.inv_dt = 10;
  l.kind = kind;
  l.m = 0.4;
  l.mu = 0.2;
  l.k_weight = 50;
  l.a = 0.01;
  return l;
}

void check_derivatives(const PairKinematics& k, const RowLaw& l, const std::array<Vec2, 3>& v, bool potential) {
  const unit::DenseRowTerm r = unit::dense_row_term(k, l, v);
  const int nd = 2 * k.k;
  for (int j = 0; j < nd; ++j) {
    const double h = 1e-7;
    auto vp = v, vm = v;
    vp[j / 2](j % 2) += h;
    vm[j / 2](j % 2) -= h;
    const unit::DenseRowTerm rp = unit::dense_row_term(k, l, vp), rm = unit::dense_row_term(k, l, vm);
    if (potential) EXPECT_NEAR(r.grad[j], (rp.energy - rm.energy) / (2 * h), 1e-5 * (1 + std::abs(r.grad[j]))) << j;
    for (int i = 0; i < nd; ++i) {
      const double fd = (rp.grad[i] - rm.grad[i]) / (2 * h);
      EXPECT_NEAR(r.hess[j * nd + i], fd, 1e-5 * (1 + std::abs(fd))) << i << "," << j;
    }
  }
}

// A pressing pair sliding slowly, Coulomb below the sticking cap (B = mu N).
const std::array<Vec2, 3> kSliding{Vec2(0.003, -0.5), Vec2(0.0, 0.2), Vec2(0.0, 0.1)};
RowLaw coulomb_below_cap() {
  RowLaw l = law(FrictionLaw::Kind::Coulomb);
  l.k_weight = 1e4;
  return l;
}

}  // namespace

TEST(PenaltyPair, NormalTermMatchesFiniteDifferences) {
  const std::array<Vec2, 3> v{Vec2(0.1, -0.5), Vec2(0.05, 0.2), Vec2(-0.1, 0.1)};
  check_derivatives(body_pair(), law(FrictionLaw::Kind::None), v, true);
}

TEST(PenaltyPair, FrictionFactorIsAPotentialWithExactHessian) {
  for (double slip : {-0.3, -0.004, 0.0, 0.002, 0.5}) {
    const std::array<Vec2, 3> v{Vec2(slip, -0.5), Vec2(0.0, 0.2), Vec2(0.0, 0.1)};
    check_derivatives(body_pair(), law(FrictionLaw::Kind::Factor), v, true);
  }
}

TEST(PenaltyPair, CoulombTangentIsConsistentAndUnsymmetric) {
  const std::array<Vec2, 3>& v = kSliding;
  const PairKinematics k = body_pair();
  const RowLaw l = coulomb_below_cap();
  const unit::DenseRowTerm r = unit::dense_row_term(k, l, v);
  ASSERT_GT(r.normal_force, 0);                        // pressing
  ASSERT_LT(l.mu * r.normal_force, l.k_weight);        // below the sticking cap: B = mu N
  EXPECT_NEAR(r.bound, l.mu * r.normal_force, 1e-12);
  check_derivatives(k, l, v, false);
  double asym = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) asym = std::max(asym, std::abs(r.hess[j * 6 + i] - r.hess[i * 6 + j]));
  EXPECT_GT(asym, 1e-3);
  // Capped at k w: B no longer depends on N, the tangent is symmetric again.
  RowLaw capped = l;
  capped.k_weight = 1e-3;
  const unit::DenseRowTerm c = unit::dense_row_term(k, capped, v);
  EXPECT_NEAR(c.bound, 1e-3, 1e-15);
  check_derivatives(k, capped, v, true);
}

// The line search's merit with Coulomb friction (ContactFormulation::
// anchor_merit): the bound frozen at an iterate v0 makes the energy a
// potential whose gradient at v0 is the live term's gradient (the residual),
// while gradient and Hessian stay the live, unsymmetric ones.
TEST(PenaltyPair, CoulombMeritAnchoredAtAnIterateHasTheResidualAsGradient) {
  const std::array<Vec2, 3>& v0 = kSliding;
  const PairKinematics k = body_pair();
  const RowLaw l = coulomb_below_cap();
  const unit::DenseRowTerm live = unit::dense_row_term(k, l, v0);
  ASSERT_GT(live.bound, 0);
  RowLaw anchored = l;
  anchored.merit_bound = live.bound;
  const unit::DenseRowTerm r = unit::dense_row_term(k, anchored, v0);
  double grad_error = 0, live_fd_error = 0;
  for (int j = 0; j < 6; ++j) {
    EXPECT_EQ(r.grad[j], live.grad[j]);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(r.hess[j * 6 + i], live.hess[j * 6 + i]);
    const double h = 1e-7;
    auto vp = v0, vm = v0;
    vp[j / 2](j % 2) += h;
    vm[j / 2](j % 2) -= h;
    const double fd = (unit::dense_row_term(k, anchored, vp).energy - unit::dense_row_term(k, anchored, vm).energy) / (2 * h);
    const double fd_live = (unit::dense_row_term(k, l, vp).energy - unit::dense_row_term(k, l, vm).energy) / (2 * h);
    grad_error = std::max(grad_error, std::abs(fd - r.grad[j]) / (1 + std::abs(r.grad[j])));
    live_fd_error = std::max(live_fd_error, std::abs(fd_live - r.grad[j]) / (1 + std::abs(r.grad[j])));
  }
  EXPECT_LT(grad_error, 1e-6);
  // Without the anchor the energy's gradient is not the term's gradient.
  EXPECT_GT(live_fd_error, 1e-3);
}

TEST(PenaltyPair, ActionEqualsReaction) {
  const std::array<Vec2, 3> v{Vec2(0.2, -0.5), Vec2(0.01, 0.2), Vec2(-0.03, 0.1)};
  const unit::DenseRowTerm r = unit::dense_row_term(body_pair(), law(FrictionLaw::Kind::Coulomb), v);
  Vec2 sum = Vec2::Zero();
  for (int a = 0; a < 3; ++a) sum += Vec2(r.grad[2 * a], r.grad[2 * a + 1]);
  EXPECT_LT(sum.norm(), 1e-12 * Vec2(r.grad[0], r.grad[1]).norm());
}

TEST(PenaltyPair, GapCorrectionAimsAtZeroGapAtTheEndOfTheStep) {
  // A die pair: the node at rest against a die moving at 1 mm/s toward it,
  // 0.01 mm inside. Minimizing the penalty alone: gamma_N = -g0/dt.
  PairKinematics k;
  k.k = 1;
  k.n = Vec2(0, 1);
  k.offset = Vec2(0, -1);
  k.gap0 = k.gap_from = -0.01;
  RowLaw l = law(FrictionLaw::Kind::None);
  // r = (v - v_die).n + g0/dt = 0 at v_y = -1 + 0.01 * 10.
  const unit::DenseRowTerm r = unit::dense_row_term(k, l, {Vec2(0, -0.9), Vec2::Zero(), Vec2::Zero()});
  EXPECT_NEAR(r.gamma_n, 0.1, 1e-15);
  EXPECT_NEAR(r.normal_force, 0.0, 1e-12);
}

TEST(PenaltyPair, OneSidedPenaltyActsOnlyOnPredictedPenetration) {
  // A free node 0.01 mm above a die that stands still, dt = 0.1 s: it lands
  // within the step if it closes faster than 0.1 mm/s.
  PairKinematics k;
  k.k = 1;
  k.n = Vec2(0, 1);
  k.gap0 = k.gap_from = 0.01;
  RowLaw l = law(FrictionLaw::Kind::None);
  l.one_sided = true;
  const auto at = [&](double vy) { return unit::dense_row_term(k, l, {Vec2(0.3, vy), Vec2::Zero(), Vec2::Zero()}); };
  // Would stop short: no force, no stiffness.
  const unit::DenseRowTerm free = at(-0.05);
  EXPECT_EQ(free.normal_force, 0.0);
  EXPECT_EQ(free.energy, 0.0);
  for (double h : free.hess) EXPECT_EQ(h, 0.0);
  // Would end 0.02 mm inside: pushed out, N = -beta r with r = -0.3 + 0.1.
  const unit::DenseRowTerm in = at(-0.3);
  EXPECT_NEAR(in.normal_force, l.beta * 0.2, 1e-9);
  // Derivatives exact on each side of the kink, continuous force across it.
  check_derivatives(k, l, {Vec2(0.3, -0.3), Vec2::Zero(), Vec2::Zero()}, true);
  check_derivatives(k, l, {Vec2(0.3, -0.05), Vec2::Zero(), Vec2::Zero()}, true);
  EXPECT_NEAR(at(-0.1 - 1e-9).normal_force, 0.0, 1e-5);
  // A body pair in the same state: the master's velocity counts.
  PairKinematics b = body_pair();
  b.gap0 = b.gap_from = 0.01;
  check_derivatives(b, l, {Vec2(0.1, -0.5), Vec2(0.05, 0.2), Vec2(-0.1, 0.1)}, true);
  EXPECT_GT(unit::dense_row_term(b, l, {Vec2(0.1, -0.5), Vec2(0.05, 0.2), Vec2(-0.1, 0.1)}).normal_force, 0.0);
}

TEST(HallquistRule, TheBodyThatPenetratesBecomesTheSlave) {
  Penetrations none, some{3, 0.01}, more{5, 0.02};
  EXPECT_EQ(hallquist_slave(0, none, none), 0);  // nothing penetrates: keep
  EXPECT_EQ(hallquist_slave(0, none, some), 1);  // the master's nodes penetrate: switch
  EXPECT_EQ(hallquist_slave(1, some, none), 0);
  EXPECT_EQ(hallquist_slave(0, more, some), 0);  // the slave's own penetrate more: keep
  EXPECT_EQ(hallquist_slave(1, some, some), 1);  // a tie keeps the roles
  // The guard (the depth that made the last switch): switching back needs
  // the master's nodes deeper than that.
  EXPECT_EQ(hallquist_slave(0, none, some, 0.02), 0);
  EXPECT_EQ(hallquist_slave(0, none, more, 0.01), 1);
}

TEST(HallquistRule, PenetrationsCountedOnCraftedSurfaces) {
  // Lower body's top y = 0 (walked right to left); upper body's bottom
  // y = 0.1 walked left to right with two nodes pushed below y = 0.
  std::vector<Vec2> x;
  ContactSurface lower, upper;
  for (int i = 0; i <= 4; ++i) x.emplace_back(4 - i, 0.0);
  for (Index i = 0; i < 4; ++i) lower.edges.push_back({i, i + 1, 0});
  for (Index i = 0; i <= 4; ++i) lower.nodes.push_back(i);
  for (int i = 0; i <= 4; ++i) x.emplace_back(i + 0.5, (i == 1 || i == 2) ? -0.05 : 0.1);
  for (Index i = 5; i < 9; ++i) upper.edges.push_back({i, i + 1, 1});
  for (Index i = 5; i <= 9; ++i) upper.nodes.push_back(i);
  const SegmentGrid g_lower(x, lower, 0.5), g_upper(x, upper, 0.5);
  const Penetrations up_into_low = count_penetrations(find_segments(x, upper, lower, g_lower, 0.5), 1e-3);
  const Penetrations low_into_up = count_penetrations(find_segments(x, lower, upper, g_upper, 0.5), 1e-3);
  EXPECT_EQ(up_into_low.count, 2);
  EXPECT_NEAR(up_into_low.deepest, 0.05, 1e-12);
  // The roles switch to make the upper body the slave if it was the master.
  EXPECT_EQ(hallquist_slave(1, up_into_low, low_into_up), 0);
  EXPECT_EQ(up_into_low.count > low_into_up.count, true);
}
