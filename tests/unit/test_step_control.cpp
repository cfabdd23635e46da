// Step control by a local error estimate (model/step_control.hpp) and the
// recovery-based strain-rate error (mesh/error_indicator.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/error_indicator.hpp"
#include "fem/quad4.hpp"
#include "mesh/generate.hpp"
#include "model/step_control.hpp"

using namespace rpfem;

namespace {
// One element on the unit square, law n: sigma = K (eps0 + eps)^n.
struct OneElement {
  Mesh m = make_rectangle("b", {0, 0, 1, 1, 1, 1});
  FlowStressLaw law;
  std::vector<std::array<double, 4>> eps{{0.1, 0.1, 0.1, 0.1}}, rate{{1, 1, 1, 1}};
  double estimate(double dt, const std::vector<Vec2>& v0, const std::vector<Vec2>& vh, double L,
                  const std::vector<std::array<double, 4>>& rh) const {
    return step_error_estimate(m, Geometry::PlaneStrain, m.x, dt, v0, vh, eps, rate, rh, {{&law}}, L);
  }
};
}  // namespace

// The estimate is Euler's local error: a body translated by u with
// u' = -u (v = -u at every node), from u0 over dt, the midpoint's
// half-step velocity -u0 (1 - dt/2) against -u0 gives dt^2 u0 / 2, the
// leading term of u0 e^-dt - u0 (1 - dt); a translation changes no volume.
TEST(StepControl, EstimateIsEulersLocalErrorInTheMotion) {
  OneElement b;
  b.law.K = 100, b.law.n = 0;  // no hardening: the strain adds nothing
  const double u0 = 2.0, L = 4.0;
  for (double dt : {1e-1, 1e-2, 1e-3}) {
    const std::vector<Vec2> v0(4, Vec2(-u0, 0)), vh(4, Vec2(-u0 * (1 - dt / 2), 0));
    const double e = b.estimate(dt, v0, vh, L, b.rate);
    const double exact = std::abs(u0 * std::exp(-dt) - u0 * (1 - dt)) / L;
    EXPECT_NEAR(e / exact, 1.0, dt) << dt;
  }
}

// In the strain: the flow stress's change between the Euler and the
// midpoint strain, sigma = K (eps0 + eps)^n, over the element's mean flow
// stress (one point of four changes).
TEST(StepControl, EstimateInTheFlowStress) {
  OneElement b;
  b.law.K = 100, b.law.n = 0.2, b.law.eps0 = 0.02;
  const double dt = 0.1;
  const std::vector<Vec2> v(4, Vec2(1, 0));
  const double e = b.estimate(dt, v, v, 1.0, {{1, 1.2, 1, 1}});
  const double s20 = b.law.yield(0.2), s22 = b.law.yield(0.22);
  EXPECT_NEAR(e, (s22 - s20) / (3 * s20 + s22), 1e-14);
}

// In the volume: a half-step velocity that stretches the element,
// v = (a x, 0), against none: |V_M - V_E| / V_M = dt a / (1 + dt a); added
// to the flow stress's.
TEST(StepControl, EstimateInTheVolume) {
  OneElement b;
  b.law.K = 100, b.law.n = 0;
  const double dt = 0.1, a = 0.5;
  const std::vector<Vec2> v0(4, Vec2::Zero());
  std::vector<Vec2> vh(4);
  for (int i = 0; i < 4; ++i) vh[i] = Vec2(a * b.m.x[i](0), 0);
  EXPECT_NEAR(b.estimate(dt, v0, vh, 1e9, b.rate), dt * a / (1 + dt * a), 1e-14);
  b.law.n = 0.2, b.law.eps0 = 0.02;
  const double s20 = b.law.yield(0.2), s22 = b.law.yield(0.22);
  EXPECT_NEAR(b.estimate(dt, v0, vh, 1e9, {{1, 1.2, 1, 1}}), dt * a / (1 + dt * a) + (s22 - s20) / (3 * s20 + s22),
              1e-14);
}

// The elements' errors weighted by their flow stress times volume (the
// sum's relative error, a load's): one element of two in error, the two
// alike, gives about half its own.
TEST(StepControl, EstimateWeightsTheElements) {
  const Mesh m = make_rectangle("b", {0, 0, 2, 1, 2, 1});
  FlowStressLaw law;
  law.K = 100, law.n = 0.2, law.eps0 = 0.02;
  const std::vector<Vec2> v(m.x.size(), Vec2::Zero());
  const std::vector<std::array<double, 4>> eps(2, {0.1, 0.1, 0.1, 0.1}), r0(2, {1, 1, 1, 1});
  std::vector<std::array<double, 4>> rh = r0;
  rh[0] = {1.2, 1.2, 1.2, 1.2};
  const double dt = 0.1;
  const double e = step_error_estimate(m, Geometry::PlaneStrain, m.x, dt, v, v, eps, r0, rh, {{&law}, {&law}}, 1.0);
  const double s20 = law.yield(0.2), s22 = law.yield(0.22);
  EXPECT_NEAR(e, (s22 - s20) / (s22 + s20), 1e-14);
}

// The increment (2): e = bound gives the safety factor; the changes
// bounded by fac_min and fac_max of the base; a rejection never grows.
TEST(StepControl, NextIncrement) {
  const StepControlFactors f;
  EXPECT_DOUBLE_EQ(next_increment(0.1, 1e-3, 1e-3, 0.1, false), 0.1 * f.safety);
  EXPECT_DOUBLE_EQ(next_increment(0.1, 0.0, 1e-3, 0.1, false), 0.1 * f.fac_max);
  EXPECT_DOUBLE_EQ(next_increment(0.1, 1.0, 1e-3, 0.1, true), 0.1 * f.fac_min);
  EXPECT_DOUBLE_EQ(next_increment(0.1, 1e-6, 1e-3, 0.1, true), 0.1);
  // A step a landing ended at 0.01 of a proposed 0.1: grows from the proposal.
  EXPECT_DOUBLE_EQ(next_increment(0.01, 1e-9, 1e-3, 0.1, false), 0.1 * f.fac_max);
  EXPECT_DOUBLE_EQ(step_error_bound(1e-3, 0.05, 5.0), 1e-5);
}

// A linear rate field is recovered exactly: the estimate is zero; a field
// that jumps between elements is not, and its largest element values lie
// at the jump.
TEST(StrainRateErrorIndicator, ZeroForLinearLargestAtAJump) {
  const Mesh m = make_rectangle("b", {0, 0, 4, 2, 8, 4});
  const Index ne = m.num_elements();
  std::vector<std::array<double, 4>> rate(ne);
  for (Index e = 0; e < ne; ++e)
    for (int q = 0; q < 4; ++q) {
      const Eigen::Vector4d N = quad4_shape(kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
      Vec2 p = Vec2::Zero();
      for (int a = 0; a < 4; ++a) p += N(a) * m.x[m.quads[e][a]];
      rate[e][q] = 1 + 0.5 * p(0) - 0.25 * p(1);
    }
  for (Geometry g : {Geometry::PlaneStrain, Geometry::Axisymmetric}) {
    const StrainRateError z = strain_rate_error(m, m.x, rate, g);
    EXPECT_LT(z.relative, 1e-12);
  }
  Index worst = 0;
  for (Index e = 0; e < ne; ++e) {
    Vec2 c = Vec2::Zero();
    for (int a = 0; a < 4; ++a) c += 0.25 * m.x[m.quads[e][a]];
    for (int q = 0; q < 4; ++q) rate[e][q] = c(0) < 2 ? 1.0 : 2.0;
  }
  const StrainRateError z = strain_rate_error(m, m.x, rate, Geometry::PlaneStrain);
  for (Index e = 0; e < ne; ++e)
    if (z.element_rms[e] > z.element_rms[worst]) worst = e;
  Vec2 c = Vec2::Zero();
  for (int a = 0; a < 4; ++a) c += 0.25 * m.x[m.quads[worst][a]];
  EXPECT_NEAR(c(0), 2.0, 0.5 + 1e-12);  // an element next to x = 2
  EXPECT_GT(z.relative, 1e-2);
}
