// The friction term with its bound fixed in a solve (contact/row_terms.*,
// as ipopt and direct use it): gradient and Hessian against finite
// differences of its energy and gradient (a potential), and the bound of
// each law.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/row_terms.hpp"
#include "dense_row_term.hpp"

using namespace rpfem;

namespace {
unit::DenseRowTerm friction_term(const PairKinematics& k, double B, double a, const std::array<Vec2, 3>& v) {
  RowLaw l;
  l.normal = false;
  l.fixed_bound = B;
  l.a = a;
  return unit::dense_row_term(k, l, v);
}
}  // namespace

TEST(IpoptFriction, TermIsAPotentialWithExactHessian) {
  PairKinematics k;
  k.k = 3;
  k.nodes = {0, 1, 2};
  k.c = {1.0, -0.7, -0.3};
  k.n = Vec2(0.3, 1.0).normalized();
  const double B = 40, a = 0.01;
  for (double slip : {-0.3, -0.004, 0.0, 0.002, 0.5}) {
    const std::array<Vec2, 3> v{Vec2(slip, -0.5), Vec2(0.0, 0.2), Vec2(0.01, 0.1)};
    const unit::DenseRowTerm t = friction_term(k, B, a, v);
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-7;
      auto vp = v, vm = v;
      vp[j / 2](j % 2) += h;
      vm[j / 2](j % 2) -= h;
      const unit::DenseRowTerm p = friction_term(k, B, a, vp), m = friction_term(k, B, a, vm);
      EXPECT_NEAR(t.grad[j], (p.energy - m.energy) / (2 * h), 1e-5 * (1 + std::abs(t.grad[j]))) << j;
      for (int i = 0; i < 6; ++i) {
        const double fd = (p.grad[i] - m.grad[i]) / (2 * h);
        EXPECT_NEAR(t.hess[j * 6 + i], fd, 1e-5 * (1 + std::abs(fd))) << i << "," << j;
        EXPECT_EQ(t.hess[j * 6 + i], t.hess[i * 6 + j]);
      }
    }
  }
}

TEST(IpoptFriction, BoundsOfTheLaws) {
  FrictionLaw factor, coulomb, none;
  factor.kind = FrictionLaw::Kind::Factor;
  factor.m = 0.3;
  coulomb.kind = FrictionLaw::Kind::Coulomb;
  coulomb.mu = 0.2;
  EXPECT_DOUBLE_EQ(friction_bound(factor, true, 5.0, 100.0), 30.0);    // m k w
  EXPECT_DOUBLE_EQ(friction_bound(factor, false, 5.0, 100.0), 0.0);    // not in contact
  EXPECT_DOUBLE_EQ(friction_bound(coulomb, true, 50.0, 100.0), 10.0);  // mu N
  EXPECT_DOUBLE_EQ(friction_bound(coulomb, true, 1e4, 100.0), 100.0);  // capped at k w
  EXPECT_DOUBLE_EQ(friction_bound(coulomb, true, -1.0, 100.0), 0.0);   // tension
  EXPECT_DOUBLE_EQ(friction_bound(none, true, 50.0, 100.0), 0.0);
}
