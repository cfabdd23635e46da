// Requirement (kernel): observed L2 order of the velocity error
// of a manufactured solution >= 1.8 on a sequence of four meshes.
#include <gtest/gtest.h>

#include <cstdio>

#include "mms.hpp"

using namespace rpfem;

class Mms : public ::testing::TestWithParam<Geometry> {};

//~ feature = "mms"
//~ scene = "verification/mms.cpp on 4 x 4, 8 x 8, 16 x 16 and 32 x 32 meshes, plane strain and axisymmetric"
//~ source = "Roache 2002 (method of manufactured solutions); bilinear elements' L2 order 2"
//~ [[check]]
//~ what = "observed L2 order of the velocity error between successive meshes"
//~ compares = "manufactured solution"
//~ tolerance = "order >= 1.8"
//~ why = "the asymptotic order of bilinear quadrilaterals is 2; 1.8 allows the coarsest pair's pre-asymptotic error and fails on a first-order error (a wrong quadrature, B matrix or load)"
//~ [[check]]
//~ what = "Newton converges on every mesh"
//~ compares = "expected behaviour"
//~ tolerance = "converged"
//~ why = "an unconverged solve has no error to measure"
TEST_P(Mms, VelocityConvergesAtSecondOrder) {
  std::vector<MmsResult> r;
  for (int n : {4, 8, 16, 32}) {
    r.push_back(run_mms(GetParam(), n));
    ASSERT_TRUE(r.back().converged) << "Newton did not converge on the " << n << "x" << n << " mesh";
  }
  const auto p = observed_orders(r);
  for (std::size_t i = 0; i < r.size(); ++i)
    std::printf("[measured] n = %2d  L2 error %.4e  Newton %d  order %s\n", r[i].n, r[i].l2_error,
                r[i].newton_iterations, i ? std::to_string(p[i - 1]).c_str() : "-");
  for (double order : p) EXPECT_GE(order, 1.8);
}

INSTANTIATE_TEST_SUITE_P(Kernel, Mms, ::testing::Values(Geometry::PlaneStrain, Geometry::Axisymmetric),
                         [](const auto& info) {
                           return std::string(info.param == Geometry::PlaneStrain ? "PlaneStrain" : "Axisymmetric");
                         });

// Requirement (kernel): the recovery-based (Zienkiewicz-Zhu) estimate of
// the strain-rate error (mesh/error_indicator.hpp) measures the true error
// of the manufactured solution.
class MmsIndicator : public ::testing::TestWithParam<Geometry> {};

//~ feature = "mms"
//~ scene = "verification/mms.cpp on 4 x 4, 8 x 8, 16 x 16 and 32 x 32 meshes, plane strain and axisymmetric"
//~ source = "Zienkiewicz and Zhu, IJNME 33 (1992) 1331 (superconvergent patch recovery; the estimate's effectivity tends to 1)"
//~ [[check]]
//~ what = "effectivity: the global relative estimate of the effective strain rate's L2 error over the true relative error (3x3 Gauss against the manufactured field)"
//~ compares = "manufactured solution"
//~ tolerance = "between 1/3 and 3 on every mesh"
//~ why = "the effectivity an error-controlled mesh needs to meet a stated accuracy within a factor of 3; a wrong recovery, weight or norm moves it by more"
//~ [[check]]
//~ what = "the estimate falls with the mesh size"
//~ compares = "manufactured solution"
//~ tolerance = "smaller on each finer mesh"
//~ why = "the true error falls at order 1; an estimate that does not fall does not follow it"
TEST_P(MmsIndicator, StrainRateEstimateWithinFactorThree) {
  double last = INFINITY;
  for (int n : {4, 8, 16, 32}) {
    const MmsResult r = run_mms(GetParam(), n);
    ASSERT_TRUE(r.converged) << "Newton did not converge on the " << n << "x" << n << " mesh";
    const double eff = r.strain_rate_estimate / r.strain_rate_error;
    std::printf("[measured] n = %2d  strain-rate error %.4e  estimate %.4e  effectivity %.3f\n", n,
                r.strain_rate_error, r.strain_rate_estimate, eff);
    EXPECT_GT(eff, 1.0 / 3) << n;
    EXPECT_LT(eff, 3.0) << n;
    EXPECT_LT(r.strain_rate_estimate, last) << n;
    last = r.strain_rate_estimate;
  }
}

INSTANTIATE_TEST_SUITE_P(Kernel, MmsIndicator, ::testing::Values(Geometry::PlaneStrain, Geometry::Axisymmetric),
                         [](const auto& info) {
                           return std::string(info.param == Geometry::PlaneStrain ? "PlaneStrain" : "Axisymmetric");
                         });
