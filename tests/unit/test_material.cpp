// The flow-stress law, its potential and rate tangent against finite
// differences, continuity at the limiting strain rate, the library.
#include <gtest/gtest.h>

#include <cmath>

#include "core/types.hpp"
#include "material/flow_stress.hpp"

using namespace rpfem;

TEST(Material, LibraryConvertsKgfToMPa) {
  const LibraryMaterial* m = find_library_material("AISI1035");
  ASSERT_NE(m, nullptr);
  EXPECT_DOUBLE_EQ(m->K_kgf_mm2, 91.97);
  EXPECT_DOUBLE_EQ(m->n, 0.17);
  EXPECT_NEAR(m->K_kgf_mm2 * kKgfPerMm2ToMPa, 901.9176, 1e-3);
  EXPECT_NE(find_library_material("AISI1010"), nullptr);
  EXPECT_EQ(find_library_material("unobtainium"), nullptr);
}

TEST(Material, YieldWithOffset) {
  FlowStressLaw l{100.0, 0.2, 0.05, 0.0, 1.0};
  EXPECT_NEAR(l.yield(0.0), 100 * std::pow(0.05, 0.2), 1e-12);
  EXPECT_NEAR(l.yield(0.45), 100 * std::pow(0.5, 0.2), 1e-12);
}

class FlowFD : public ::testing::TestWithParam<double> {};

TEST_P(FlowFD, PotentialDerivativesMatchFiniteDifferences) {
  FlowStressLaw l{500.0, 0.2, 0.02, GetParam(), 0.5};
  const double lim = 1e-3;
  for (double r : {1e-5, 5e-4, 2e-3, 0.1, 3.0}) {
    const FlowPoint p = flow_point(l, 0.3, r, lim);
    const double h = 1e-7 * std::max(r, 1e-4);
    const FlowPoint a = flow_point(l, 0.3, r + h, lim), b = flow_point(l, 0.3, r - h, lim);
    EXPECT_NEAR(p.sigma, (a.phi - b.phi) / (2 * h), 1e-6 * (1 + p.sigma)) << "rate " << r;
    EXPECT_NEAR(p.dsigma, (a.sigma - b.sigma) / (2 * h), 1e-5 * (1 + std::abs(p.dsigma))) << "rate " << r;
    EXPECT_EQ(p.rigid, r < lim);
  }
  // Continuity of phi and sigma at the limiting rate.
  const FlowPoint below = flow_point(l, 0.3, lim * (1 - 1e-12), lim), above = flow_point(l, 0.3, lim, lim);
  EXPECT_NEAR(below.phi, above.phi, 1e-9 * above.phi);
  EXPECT_NEAR(below.sigma, above.sigma, 1e-9 * above.sigma);
}

INSTANTIATE_TEST_SUITE_P(Material, FlowFD, ::testing::Values(0.0, 0.05, 0.2));

TEST(Material, RateIndependentAboveLimit) {
  FlowStressLaw l{500.0, 0.2, 0.02, 0.0, 1.0};
  EXPECT_NEAR(flow_point(l, 0.1, 0.5, 1e-3).sigma, l.yield(0.1), 1e-12);
  EXPECT_NEAR(flow_point(l, 0.1, 50, 1e-3).sigma, l.yield(0.1), 1e-12);
  EXPECT_EQ(flow_point(l, 0.1, 50, 1e-3).dsigma, 0.0);
}
