// Load-stroke curve comparison (verification/curve_comparison.*): exact
// for equal curves, the relative gap for scaled ones, and a staircase
// shifted by less than the stroke tolerance compared by its shape.
#include <gtest/gtest.h>

#include "curve_comparison.hpp"

using namespace rpfem;

TEST(CurveComparison, EqualAndScaledCurves) {
  const std::vector<double> s{0, 1, 2, 3}, F{0, 10, 30, 40};
  EXPECT_EQ(curve_difference(s, F, s, F, 0, 0).worst, 0.0);
  const std::vector<double> G{0, 10.3, 30.9, 41.2};
  const CurveDifference d = curve_difference(s, G, s, F, 0.5, 0);
  EXPECT_NEAR(d.worst, 0.03, 1e-12);
  EXPECT_EQ(d.points, 3);
  // Points of A between B's vertices are compared with B interpolated.
  EXPECT_NEAR(curve_difference({1.5}, {20}, s, F, 0, 0).worst, 0.0, 1e-15);
}

TEST(CurveComparison, StrokeToleranceAbsorbsAShiftedStaircase) {
  // B jumps from 10 to 20 at s = 1.0; A at s = 0.98 already carries 20.
  const std::vector<double> sb{0, 0.999, 1.0, 2}, Fb{0, 10, 20, 30};
  const std::vector<double> sa{0.98}, Fa{20};
  EXPECT_GT(curve_difference(sa, Fa, sb, Fb, 0, 0).worst, 0.9);
  EXPECT_EQ(curve_difference(sa, Fa, sb, Fb, 0, 0.05).worst, 0.0);
  // Beyond the band: 25 at s = 0.98 is 5 above B's largest load in
  // [0.93, 1.03] (20.3), relative to B(0.98) = 9.81.
  EXPECT_NEAR(curve_difference(sa, {25}, sb, Fb, 0, 0.05).worst, (25 - 20.3) / (10 * 0.98 / 0.999), 1e-9);
}

TEST(CurveJump, ScoresAJumpNotATrend) {
  // A straight line and a parabola have no jump beyond their trend (the
  // neighbours' mean slope is the step's own on a parabola); one step that
  // drops the load by 20 % scores about 0.2 / 0.8 there.
  std::vector<double> s, line, parabola, dropped;
  for (int i = 0; i <= 20; ++i) {
    const double x = 0.025 * i;
    s.push_back(x);
    line.push_back(70 + 40 * x);
    parabola.push_back(70 + 40 * x - 20 * x * x);
    dropped.push_back(x < 0.149 ? 70 + 40 * x : 0.8 * (70 + 40 * x));
  }
  EXPECT_LT(curve_jump(s, line, 0).worst, 1e-14);
  EXPECT_LT(curve_jump(s, parabola, 0).worst, 1e-14);
  const CurveDifference d = curve_jump(s, dropped, 0);
  EXPECT_NEAR(d.at_stroke, 0.15, 1e-12);
  EXPECT_GT(d.worst, 0.2);
  EXPECT_LT(d.worst, 0.3);
  // From past the drop, nothing.
  EXPECT_LT(curve_jump(s, dropped, 0.2).worst, 1e-14);
}

TEST(CurveJump, AShortStepDoesNotSetTheTrend) {
  // A straight line with one step cut to 1e-4 of the others (a landing):
  // no jump; the same short step carrying a 5 % leap scores it, there or
  // at the step before (whose trend the leap enters).
  const std::vector<double> s{0, 0.1, 0.2, 0.2001, 0.3, 0.4, 0.5};
  std::vector<double> F, leap;
  for (double x : s) F.push_back(100 + 50 * x), leap.push_back(100 + 50 * x + (x > 0.2 ? 5 : 0));
  EXPECT_LT(curve_jump(s, F, 0).worst, 1e-14);
  const CurveDifference d = curve_jump(s, leap, 0);
  EXPECT_GE(d.at_stroke, 0.2 - 1e-12);
  EXPECT_LE(d.at_stroke, 0.2001 + 1e-12);
  EXPECT_GT(d.worst, 5 / 115.005 - 1e-6);
  EXPECT_LT(d.worst, 5 / 110.0 + 1e-6);
}
