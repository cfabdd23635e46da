// The remesher's size from the strain-rate error (model/error_size_field.hpp):
// smaller where the indicator is larger, within its bounds, and by the
// a-priori rate the new mesh meets the target exactly where no bound acts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "mesh/error_indicator.hpp"
#include "fem/quad4.hpp"
#include "mesh/generate.hpp"
#include "model/error_size_field.hpp"

using namespace rpfem;

namespace {

// A rate field with a steep ridge along x = 1.3 (tanh over 0.1 mm): the
// indicator peaks there and is small away from it.
std::vector<GaussValues> ridge(const Mesh& m) {
  std::vector<GaussValues> rate(m.num_elements());
  for (Index e = 0; e < m.num_elements(); ++e)
    for (int q = 0; q < 4; ++q) {
      const Eigen::Vector4d N = quad4_shape(kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
      Vec2 p = Vec2::Zero();
      for (int a = 0; a < 4; ++a) p += N(a) * m.x[m.quads[e][a]];
      rate[e][q] = 1.5 + std::tanh((p(0) - 1.3) / 0.1) + 0.1 * p(1);
    }
  return rate;
}

Vec2 centre(const Mesh& m, Index e) {
  Vec2 c = Vec2::Zero();
  for (Index n : m.quads[e]) c += 0.25 * m.x[n];
  return c;
}

}  // namespace

TEST(ErrorSizeField, SmallerWhereTheIndicatorIsLargerWithinTheBounds) {
  const Mesh m = make_rectangle("b", {0, 0, 4, 2, 16, 8});  // 0.25 mm squares
  const auto rate = ridge(m);
  for (Geometry g : {Geometry::PlaneStrain, Geometry::Axisymmetric}) {
    const StrainRateError z = strain_rate_error(m, m.x, rate, g);
    const ErrorSizeRule rule{0.25 * z.relative, 0.1, 0.6};
    const ErrorSizes s = error_sizes(m, m.x, rate, g, rule);
    ASSERT_EQ(s.element.size(), static_cast<std::size_t>(m.num_elements()));
    ASSERT_TRUE(s.at);
    EXPECT_DOUBLE_EQ(s.relative, z.relative);
    // A quarter of the error asks for more elements than there are.
    EXPECT_GT(s.predicted, m.num_elements());
    Index worst = 0, least = 0;
    for (Index e = 0; e < m.num_elements(); ++e) {
      EXPECT_GE(s.element[e], rule.min_size);
      EXPECT_LE(s.element[e], rule.max_size);
      if (z.element_eta[e] > z.element_eta[worst]) worst = e;
      if (z.element_eta[e] < z.element_eta[least]) least = e;
      // On equal elements the size falls as the element's error rises.
      for (Index f = 0; f < e; ++f)
        if (z.element_eta[e] > z.element_eta[f]) EXPECT_LE(s.element[e], s.element[f]) << e << " " << f;
    }
    EXPECT_NEAR(centre(m, worst)(0), 1.3, 0.25);
    EXPECT_LT(s.element[worst], 0.25);  // refined at the ridge
    EXPECT_GT(s.element[least], 0.25);  // coarsened away from it
    // The size at a point: within the bounds everywhere, smallest at the
    // ridge.
    double lo = INFINITY, hi = 0;
    for (double x = 0; x <= 4; x += 0.05)
      for (double y = 0; y <= 2; y += 0.1) {
        const double h = s.at(Vec2(x, y));
        lo = std::min(lo, h), hi = std::max(hi, h);
        EXPECT_GE(h, rule.min_size - 1e-12);
        EXPECT_LE(h, rule.max_size + 1e-12);
      }
    EXPECT_LT(s.at(Vec2(1.3, 1.0)), s.at(Vec2(3.5, 1.0)));
    EXPECT_NEAR(s.at(Vec2(1.3, 1.0)), lo, 0.05);
    std::printf("[measured] ridge, %s: sizes %.3f to %.3f mm (bounds 0.1, 0.6), predicted %.0f elements (%lld now)\n",
                g == Geometry::PlaneStrain ? "plane strain" : "axisymmetric", lo, hi, s.predicted,
                (long long)m.num_elements());
  }
}

// Unbounded, the sizes' count is the predicted N, and the errors the
// a-priori rate gives each new element (eta_e (h_new / h_e)^2, in N_e =
// (h_e / h_new)^2 elements) sum to the target: sum_e N_e (eta_e (h_new /
// h_e)^2)^2 = (eta_bar ||epsdot||)^2.
TEST(ErrorSizeField, UnboundedTheRuleMeetsTheTargetAndItsCount) {
  const Mesh m = make_rectangle("b", {0, 0, 4, 2, 16, 8});
  const auto rate = ridge(m);
  const StrainRateError z = strain_rate_error(m, m.x, rate, Geometry::Axisymmetric);
  for (double share : {0.1, 0.5, 2.0}) {
    const double target = share * z.relative;
    const ErrorSizes s = error_sizes(m, m.x, rate, Geometry::Axisymmetric, {target, 1e-9, 1e9});
    double count = 0, error2 = 0;
    for (Index e = 0; e < m.num_elements(); ++e) {
      const double r = 0.25 / s.element[e];  // h_e / h_new (squares of 0.25 mm)
      count += r * r;
      error2 += r * r * std::pow(z.element_eta[e] / (r * r), 2);
    }
    EXPECT_NEAR(count / s.predicted, 1, 1e-12) << share;
    EXPECT_NEAR(std::sqrt(error2) / (target * z.rate_norm), 1, 1e-12) << share;
  }
}

// No rate anywhere: nothing to grade by.
TEST(ErrorSizeField, NoneWithoutARate) {
  const Mesh m = make_rectangle("b", {0, 0, 1, 1, 2, 2});
  const ErrorSizes s = error_sizes(m, m.x, std::vector<GaussValues>(4, GaussValues{0, 0, 0, 0}),
                                   Geometry::PlaneStrain, {0.1, 0.1, 1});
  EXPECT_FALSE(s.at);
  EXPECT_TRUE(s.element.empty());
}
