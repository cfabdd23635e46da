// The penalty formulation (paper eq. 3-12) on shipped scenes: against the
// exact load and the direct formulation on flat-die upsetting, penetration
// at the default beta, action equals reaction between two bodies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analytic.hpp"
#include "core/types.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

TEST(Penalty, FlatDieUpsettingMatchesExactLoadAndDirect) {
  const std::string pen = run_case("upsetting_dies_frictionless_axisym", "--formulation penalty", 0, "_penalty");
  const std::string dir = run_case("upsetting_dies_frictionless_axisym", "--formulation direct", 0, "_direct");
  const History hp = read_history(pen + "/history.csv"), hd = read_history(dir + "/history.csv");
  ASSERT_EQ(hp.rows(), hd.rows());
  FlowStressLaw l;
  l.K = 91.97 * kKgfPerMm2ToMPa;
  l.n = 0.17;
  l.eps0 = 0.02;
  double worst_exact = 0, worst_direct = 0, worst_pen = 0;
  for (std::size_t i = 0; i < hp.rows(); ++i) {
    ASSERT_NEAR(hp.at("stroke")[i], hd.at("stroke")[i], 1e-12);
    const double H = 20.0 - 2 * hp.at("stroke")[i];
    const double F = -hp.at("top_die.Fy")[i];
    worst_exact = std::max(worst_exact, std::abs(F / upsetting_load_axisymmetric(l, 20, 20, H) - 1));
    worst_direct = std::max(worst_direct, std::abs(F / -hd.at("top_die.Fy")[i] - 1));
    worst_pen = std::max(worst_pen, hp.at("max_penetration_rel")[i]);
    // The die's load is the contact force on the billet, whole model.
    EXPECT_NEAR(hp.at("billet.contact_Fy")[i], hp.at("top_die.Fy")[i], 1e-9 * F);
  }
  EXPECT_NEAR(hp.at("stroke").back(), 5.0, 1e-9);
  EXPECT_LT(worst_exact, 5e-4);
  EXPECT_LT(worst_direct, 1e-4);
  EXPECT_LT(worst_pen, 1e-3);
  std::printf("[measured] penalty vs exact %.3e, vs direct %.3e, max penetration / element size %.3e\n",
              worst_exact, worst_direct, worst_pen);
}

TEST(Penalty, SingleActionSpherePenetrationBelowElementSizeTolerance) {
  const std::string d = run_case("paper_test1_single_action", "--set stepping.end_stroke=2.0");
  const History h = read_history(d + "/history.csv");
  EXPECT_NEAR(h.at("stroke").back(), 2.0, 1e-9);
  double worst = 0;
  for (double p : h.at("max_penetration_rel")) worst = std::max(worst, p);
  EXPECT_LT(worst, 1e-3);
  // The punch and the die carry the same load (frictionless, quasi-static).
  for (std::size_t i = 0; i < h.rows(); ++i)
    EXPECT_NEAR(h.at("top_punch.Fy")[i], -h.at("bottom_die.Fy")[i], 1e-6 * std::abs(h.at("top_punch.Fy")[i]));
  std::printf("[measured] single-action sphere to 2 mm: max penetration / element size %.3e\n", worst);
}

TEST(Penalty, TwoSpheresActionEqualsReaction) {
  const std::string d = run_case("paper_test1_double_action", "--set stepping.end_stroke=1.0");
  const History h = read_history(d + "/history.csv");
  EXPECT_NEAR(h.at("stroke").back(), 1.0, 1e-9);
  double worst = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    worst = std::max(worst, h.at("force_imbalance")[i]);
    // Whole bodies: each sphere's contact forces (punch and other sphere) balance.
    const double scale = std::abs(h.at("top_punch.Fy")[i]);
    EXPECT_NEAR(h.at("upper.contact_Fy")[i], 0.0, 1e-6 * scale + 1e-9);
    EXPECT_NEAR(h.at("top_punch.Fy")[i], -h.at("bottom_punch.Fy")[i], 1e-6 * scale + 1e-9);
  }
  EXPECT_LT(worst, 1e-8);
  std::printf("[measured] two spheres to 1 mm: worst |F_upper + F_lower| / |F| on the interface %.3e\n", worst);
}
