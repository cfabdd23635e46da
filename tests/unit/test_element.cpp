// Shape functions, B matrices (hoop term), and the element's gradient and
// Hessian against finite differences of its energy and gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fem/quad4.hpp"
#include "fem/rigid_plastic_element.hpp"

using namespace rpfem;

namespace {

Quad4Coords distorted() { return {Vec2(1.0, 0.5), Vec2(3.2, 0.7), Vec2(2.9, 2.4), Vec2(0.8, 2.1)}; }

FlowStressLaw law(double m = 0) {
  FlowStressLaw l;
  l.K = 91.97 * kKgfPerMm2ToMPa;
  l.n = 0.17;
  l.eps0 = 0.02;
  l.m = m;
  l.rate_ref = 1.0;
  return l;
}

}  // namespace

TEST(Quad4, PartitionOfUnityAndLinearReproduction) {
  const auto X = distorted();
  for (auto [xi, eta] : {std::pair{-0.3, 0.7}, std::pair{0.9, -0.9}, std::pair{0.0, 0.0}}) {
    const Quad4Point p = quad4_point(X, xi, eta);
    EXPECT_NEAR(p.N.sum(), 1.0, 1e-14);
    EXPECT_NEAR(p.dN.col(0).sum(), 0.0, 1e-13);
    // A linear field f = 2x - 3y + 1 has exact derivatives.
    Eigen::Vector4d f;
    for (int a = 0; a < 4; ++a) f(a) = 2 * X[a](0) - 3 * X[a](1) + 1;
    EXPECT_NEAR(p.dN.col(0).dot(f), 2.0, 1e-12);
    EXPECT_NEAR(p.dN.col(1).dot(f), -3.0, 1e-12);
    EXPECT_GT(p.detJ, 0);
  }
}

TEST(Quad4, AxisymmetricBReproducesRadialExpansion) {
  // v_r = c r, v_z = -2 c z: e_rr = e_tt = c, e_zz = -2c, incompressible.
  const auto X = distorted();
  const double c = 0.37;
  Vec8 v;
  for (int a = 0; a < 4; ++a) v.segment<2>(2 * a) = Vec2(c * X[a](0), -2 * c * X[a](1));
  const Quad4Point p = quad4_point(X, 0.31, -0.52);
  const Eigen::Vector4d e = strain_rate_matrix(p, Geometry::Axisymmetric) * v;
  EXPECT_NEAR(e(0), c, 1e-12);
  EXPECT_NEAR(e(1), -2 * c, 1e-12);
  EXPECT_NEAR(e(2), c, 1e-12);  // hoop v_r / r
  EXPECT_NEAR(e(3), 0.0, 1e-12);
  const Eigen::Vector4d ep = strain_rate_matrix(p, Geometry::PlaneStrain) * v;
  EXPECT_EQ(ep(2), 0.0);
}

TEST(Quad4, HoopRowIsNOverR) {
  const auto X = distorted();
  const Quad4Point p = quad4_point(X, -0.2, 0.4);
  const Mat48 B = strain_rate_matrix(p, Geometry::Axisymmetric);
  for (int a = 0; a < 4; ++a) {
    EXPECT_NEAR(B(2, 2 * a), p.N(a) / p.radius, 1e-14);
    EXPECT_EQ(B(2, 2 * a + 1), 0.0);
  }
}

TEST(Quad4, AxisymmetricVolumeOfRingIsExact) {
  // Ring r in [1, 3], z in [0, 2]: V = pi (9 - 1) 2.
  Quad4Coords X{Vec2(1, 0), Vec2(3, 0), Vec2(3, 2), Vec2(1, 2)};
  double V = 0;
  for (const auto& g : kGaussPoints2x2) V += volume_weight(quad4_point(X, g[0], g[1]), Geometry::Axisymmetric, 1.0);
  EXPECT_NEAR(V, kPi * 8 * 2, 1e-12);
}

class ElementFD : public ::testing::TestWithParam<std::tuple<Geometry, double, double>> {};

// Gradient = d energy / dv and Hessian = d gradient / dv by central
// differences, for random velocity fields, rate-independent and
// viscoplastic material, above and below the limiting strain rate.
TEST_P(ElementFD, GradientAndHessian) {
  const auto [geom, m, lim] = GetParam();
  const FlowStressLaw l = law(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 5; ++trial) {
    RigidPlasticInput in;
    in.X = distorted();
    for (int i = 0; i < 8; ++i) in.v(i) = U(rng);
    in.strain = {0.1, 0.2, 0.15, 0.3};
    in.law = &l;
    in.geometry = geom;
    in.alpha = 1e3;
    in.epsdot_lim = lim;
    ElementTerms t;
    rigid_plastic_terms(in, Tangent::Consistent, t);
    EXPECT_NEAR(t.energy, rigid_plastic_energy(in), 1e-12 * std::abs(t.energy));
    const double h = 1e-6;
    for (int i = 0; i < 8; ++i) {
      RigidPlasticInput p = in, q = in;
      p.v(i) += h;
      q.v(i) -= h;
      const double fd = (rigid_plastic_energy(p) - rigid_plastic_energy(q)) / (2 * h);
      EXPECT_NEAR(t.grad(i), fd, 1e-6 * (1 + t.grad.norm())) << "gradient " << i;
      ElementTerms tp, tq;
      rigid_plastic_terms(p, Tangent::Consistent, tp);
      rigid_plastic_terms(q, Tangent::Consistent, tq);
      const Vec8 col = (tp.grad - tq.grad) / (2 * h);
      EXPECT_LT((t.hess.col(i) - col).norm(), 1e-5 * (1 + t.hess.norm())) << "Hessian column " << i;
    }
    EXPECT_LT((t.hess - t.hess.transpose()).norm(), 1e-12 * t.hess.norm());
  }
}

INSTANTIATE_TEST_SUITE_P(
    Element, ElementFD,
    ::testing::Values(std::tuple{Geometry::Axisymmetric, 0.0, 1e-3}, std::tuple{Geometry::PlaneStrain, 0.0, 1e-3},
                      std::tuple{Geometry::Axisymmetric, 0.1, 1e-3},
                      std::tuple{Geometry::Axisymmetric, 0.0, 10.0} /* all points linear-viscous */));

TEST(Element, SecantDropsOnlyTheRadialTerm) {
  const FlowStressLaw l = law();
  RigidPlasticInput in;
  in.X = distorted();
  for (int i = 0; i < 8; ++i) in.v(i) = 0.1 * (i + 1) * (i % 2 ? -1 : 1);
  in.law = &l;
  in.alpha = 10;
  in.epsdot_lim = 1e-4;
  ElementTerms c, s;
  rigid_plastic_terms(in, Tangent::Consistent, c);
  rigid_plastic_terms(in, Tangent::Secant, s);
  // The secant matrix reproduces the gradient: K_s v = grad (phi is
  // homogeneous of degree 1 for m = 0; the penalty term is quadratic).
  EXPECT_LT((s.hess * in.v - c.grad).norm(), 1e-10 * c.grad.norm());
  // The consistent tangent maps v to the volumetric part only.
  EXPECT_GT((c.hess - s.hess).norm(), 1e-3 * s.hess.norm());
}

TEST(Element, HomogeneousCompressionGivesExactRate) {
  // v_z = -z/H, v_r = r/(2H): effective strain rate 1/H everywhere.
  const FlowStressLaw l = law();
  RigidPlasticInput in;
  in.X = {Vec2(0, 0), Vec2(2, 0), Vec2(2, 1.5), Vec2(0, 1.5)};
  const double H = 10;
  for (int a = 0; a < 4; ++a) in.v.segment<2>(2 * a) = Vec2(in.X[a](0) / (2 * H), -in.X[a](1) / H);
  in.law = &l;
  in.alpha = 1e6;
  in.epsdot_lim = 1e-6;
  const ElementPost p = rigid_plastic_post(in);
  for (double r : p.strain_rate) EXPECT_NEAR(r, 1 / H, 1e-14);
  EXPECT_NEAR(p.volumetric_rate, 0, 1e-15);
}

// The volumetric penalty acts on the element's mean dilatation,
// (1/V) int epsdot_v dV (B-bar), not on its value at the centre: checked
// against a 6x6 Gauss-Legendre integral of the exact div v on a distorted
// axisymmetric element with a field whose v_r / r varies over it (the
// centre value differs by several per cent there), and in plane strain,
// where the centre value is the mean (Flanagan and Belytschko 1981).
TEST(Element, VolumetricTermIsTheMeanDilatation) {
  const FlowStressLaw l = law();
  RigidPlasticInput in;
  in.X = {Vec2(0.1, 0.0), Vec2(1.3, 0.2), Vec2(1.5, 1.1), Vec2(0.2, 0.9)};
  for (int a = 0; a < 4; ++a) in.v.segment<2>(2 * a) = Vec2(0.4 + 0.3 * in.X[a](1), -0.2 * in.X[a](0) * in.X[a](1));
  in.law = &l;
  in.alpha = 1e6;
  in.epsdot_lim = 1e-6;
  const double gx[6] = {-0.9324695142, -0.6612093865, -0.2386191861, 0.2386191861, 0.6612093865, 0.9324695142};
  const double gw[6] = {0.1713244924, 0.3607615730, 0.4679139346, 0.4679139346, 0.3607615730, 0.1713244924};
  for (Geometry g : {Geometry::Axisymmetric, Geometry::PlaneStrain}) {
    in.geometry = g;
    double integral = 0, volume = 0;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const Quad4Point p = quad4_point(in.X, gx[i], gx[j]);
        const Eigen::Vector4d e = strain_rate_matrix(p, g) * in.v;
        const double w = volume_weight(p, g, gw[i] * gw[j]);
        integral += w * (e(0) + e(1) + e(2));
        volume += w;
      }
    const double mean = integral / volume;
    const Quad4Point c = quad4_point(in.X, 0, 0);
    const Eigen::Vector4d ec = strain_rate_matrix(c, g) * in.v;
    const double centre = ec(0) + ec(1) + ec(2);
    const ElementPost post = rigid_plastic_post(in);
    EXPECT_NEAR(post.volumetric_rate, mean, 1e-9 * std::abs(mean)) << static_cast<int>(g);
    if (g == Geometry::Axisymmetric) EXPECT_GT(std::abs(centre / mean - 1), 1e-2);
    else EXPECT_NEAR(centre, mean, 1e-9 * std::abs(mean));
    // The energy's volumetric part is (alpha / 2) V mean^2.
    RigidPlasticInput no_vol = in;
    no_vol.alpha = 0;
    EXPECT_NEAR(rigid_plastic_energy(in) - rigid_plastic_energy(no_vol), 0.5 * in.alpha * volume * mean * mean,
                1e-8 * in.alpha * volume * mean * mean);
  }
}

// The element's Hessian is formed over B's structural zeros; it must be
// the dense products' to the bit (so a run's results do not move with the
// kernel's arithmetic): (w s) B^T (P B) + (w c) g g^T per point and
// alpha V b_v b_v^T, summed as in a plain Eigen transcription, on
// distorted elements with the axis in or out, both geometries, rigid and
// plastic points and the three tangent kinds.
TEST(Element, StructuredHessianIsTheDenseProductsBits) {
  const FlowStressLaw l = law();
  const auto& P = effective_rate_metric();
  int compared = 0;
  for (int e = 0; e < 40; ++e) {
    RigidPlasticInput in;
    const double h = 0.3 + 0.05 * e, x0 = e % 4 == 0 ? 0.0 : 0.2 * e;
    in.X = {Vec2(x0, 0.1 * e), Vec2(x0 + h, 0.1 * e + 0.07 * h), Vec2(x0 + 1.1 * h, 0.1 * e + 0.9 * h),
            Vec2(x0 + 0.05 * h, 0.1 * e + h)};
    for (int k = 0; k < 8; ++k) in.v(k) = std::sin(1.7 * k + 0.3 * e) * (e % 5 == 0 ? 1e-9 : 1.0);
    in.law = &l;
    in.strain = {0.05 * e, 0.1, 0.2, 0.3};
    in.alpha = 1e7;
    in.epsdot_lim = 1e-3;
    in.geometry = e % 2 ? Geometry::PlaneStrain : Geometry::Axisymmetric;
    if (e % 7 == 0) in.viscous_floor = 0.5;
    for (Tangent t : {Tangent::Consistent, Tangent::Secant}) {
      ElementTerms terms;
      rigid_plastic_terms(in, t, terms);
      // The dense transcription.
      Mat8 H = Mat8::Zero();
      Vec8 bv = Vec8::Zero();
      double V = 0;
      for (int q = 0; q < 4; ++q) {
        const Quad4Point p = quad4_point(in.X, kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
        const double w = volume_weight(p, in.geometry, 1.0);
        const Mat48 B = strain_rate_matrix(p, in.geometry);
        bv.noalias() += w * (B.row(0) + B.row(1) + B.row(2)).transpose();
        V += w;
        const Eigen::Vector4d eps = B * in.v;
        const Eigen::Vector4d Peps = P * eps;
        const double rate = std::sqrt(std::max(eps.dot(Peps), 0.0));
        FlowPoint f = flow_point(l, in.strain[q], rate, in.epsdot_lim);
        if (in.viscous_floor > 0) {
          const double c = flow_point(l, in.strain[q], in.viscous_floor, in.epsdot_lim).sigma / in.viscous_floor;
          f.sigma = c * rate, f.dsigma = c, f.rigid = true;
        }
        const double secant = f.rigid ? f.dsigma : f.sigma / rate;
        const Vec8 g = B.transpose() * Peps;
        const Mat48 PB = P * B;
        H.noalias() += (w * secant) * B.transpose().lazyProduct(PB);
        if (t == Tangent::Consistent && !f.rigid) {
          const double c = (f.dsigma - secant) / (rate * rate);
          H.noalias() += (w * c) * g * g.transpose();
        }
      }
      bv /= V;
      H.noalias() += in.alpha * V * bv * bv.transpose();
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) EXPECT_EQ(terms.hess(i, j), H(i, j)) << e << " " << i << " " << j;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 80);
}
