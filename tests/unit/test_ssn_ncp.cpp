// The semi-smooth Newton enforcement's complementarity functions
// (formulations/ssn/ncp.hpp): their values meet the contact and friction
// conditions where they vanish, and their generalized derivatives are the
// functions' finite differences away from the kinks.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ssn/ncp.hpp"

using namespace rpfem;

namespace {

struct Point {
  double ln, lt, r, s;
};

RowFriction law(int which) {
  RowFriction f;
  if (which == 1) f.kind = RowFriction::Kind::Tresca, f.bound = 3.0;
  if (which == 2) f.kind = RowFriction::Kind::Coulomb, f.mu = 0.3, f.cap = 50.0;
  if (which == 3) f.kind = RowFriction::Kind::Coulomb, f.mu = 0.3, f.cap = 2.0;  // capped
  if (which == 4) f.kind = RowFriction::Kind::Tresca, f.bound = 3.0, f.may_stick = false;  // a node on two dies
  return f;
}

}  // namespace

TEST(SsnNcp, DerivativesAreFiniteDifferencesAwayFromKinks) {
  const double c = 7.0, h = 1e-7;
  // Points on every branch: inactive; active sticking; active slipping
  // either way; Coulomb below and at its cap.
  const std::vector<Point> points{{1.0, 0.5, 2.0, 0.1},    {5.0, 0.2, 0.1, 0.01}, {5.0, 4.0, 0.1, -2.0},
                                  {5.0, -4.0, 0.1, 2.0},   {20.0, 1.0, -0.5, 0.7}, {20.0, -30.0, -0.5, -0.7}};
  for (int which = 0; which < 5; ++which)
    for (const Point& p : points) {
      const RowFriction f = law(which);
      const RowNcp at = row_ncp(p.ln, p.lt, p.r, p.s, c, 0.6 * c, f);
      auto fd = [&](int var) {
        Point a = p, b = p;
        double* pa[] = {&a.ln, &a.lt, &a.r, &a.s};
        double* pb[] = {&b.ln, &b.lt, &b.r, &b.s};
        *pa[var] += h, *pb[var] -= h;
        const RowNcp A = row_ncp(a.ln, a.lt, a.r, a.s, c, 0.6 * c, f), B = row_ncp(b.ln, b.lt, b.r, b.s, c, 0.6 * c, f);
        return std::pair{(A.cn - B.cn) / (2 * h), (A.ct - B.ct) / (2 * h)};
      };
      const double tol = 1e-6;
      EXPECT_NEAR(at.dcn_dln, fd(0).first, tol) << which;
      EXPECT_NEAR(0.0, fd(1).first, tol) << which;
      EXPECT_NEAR(at.dcn_dr, fd(2).first, tol) << which;
      EXPECT_NEAR(0.0, fd(3).first, tol) << which;
      EXPECT_NEAR(at.dct_dln, fd(0).second, tol) << which << " lambda_N";
      EXPECT_NEAR(at.dct_dlt, fd(1).second, tol) << which << " lambda_T";
      EXPECT_NEAR(at.dct_dr, fd(2).second, tol) << which << " r";
      EXPECT_NEAR(at.dct_ds, fd(3).second, tol) << which << " gamma_T";
    }
}

TEST(SsnNcp, ZerosAreTheContactAndFrictionConditions) {
  const double c = 3.0;
  // Pressing at zero gap, sticking within the bound: both functions vanish.
  RowNcp z = row_ncp(10.0, 1.0, 0.0, 0.0, c, c, law(1));
  EXPECT_TRUE(z.active);
  EXPECT_TRUE(z.stick);
  EXPECT_DOUBLE_EQ(z.cn, 0.0);
  EXPECT_DOUBLE_EQ(z.ct, 0.0);
  // Slipping at gamma_T > 0 with the force at the bound, opposing it.
  z = row_ncp(10.0, -3.0, 0.0, 0.5, c, c, law(1));
  EXPECT_FALSE(z.stick);
  EXPECT_DOUBLE_EQ(z.ct, 0.0);
  // The same force along the slip is no solution.
  EXPECT_NE(row_ncp(10.0, 3.0, 0.0, 0.5, c, c, law(1)).ct, 0.0);
  // A sticking row that slips is no solution; nor is a force above the bound.
  EXPECT_NE(row_ncp(10.0, 1.0, 0.0, 0.1, c, c, law(1)).ct, 0.0);
  EXPECT_NE(row_ncp(10.0, 3.5, 0.0, 0.0, c, c, law(1)).ct, 0.0);
  // Open gap, no force: inactive, no friction.
  z = row_ncp(0.0, 0.0, 0.2, 0.4, c, c, law(2));
  EXPECT_FALSE(z.active);
  EXPECT_DOUBLE_EQ(z.cn, 0.0);
  EXPECT_DOUBLE_EQ(z.ct, 0.0);
  // A tensile force is no solution; nor is a penetration.
  EXPECT_NE(row_ncp(-1.0, 0.0, 0.0, 0.0, c, c, law(0)).cn, 0.0);
  EXPECT_NE(row_ncp(1.0, 0.0, -0.1, 0.0, c, c, law(0)).cn, 0.0);
  // Coulomb: the bound is mu lambda_N at zero gap, capped at k w.
  EXPECT_DOUBLE_EQ(row_ncp(10.0, 0.0, 0.0, 1.0, c, c, law(2)).g, 3.0);
  EXPECT_DOUBLE_EQ(row_ncp(10.0, 0.0, 0.0, 1.0, c, c, law(3)).g, 2.0);
  // A row that may not stick: zero force where it would, the bound where
  // it slips.
  EXPECT_DOUBLE_EQ(row_ncp(10.0, 0.0, 0.0, 0.0, c, c, law(4)).ct, 0.0);
  EXPECT_NE(row_ncp(10.0, 1.0, 0.0, 0.0, c, c, law(4)).ct, 0.0);
  EXPECT_DOUBLE_EQ(row_ncp(10.0, -3.0, 0.0, 0.5, c, c, law(4)).ct, 0.0);
}
