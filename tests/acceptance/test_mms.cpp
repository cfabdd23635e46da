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
