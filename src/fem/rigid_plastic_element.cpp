#include "fem/rigid_plastic_element.hpp"

#include <cmath>

namespace rpfem {

const Eigen::Matrix4d& effective_rate_metric() {
  static const Eigen::Matrix4d P = [] {
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = (2.0 / 3.0) * ((i == j ? 1.0 : 0.0) - 1.0 / 3.0);
    m(3, 3) = 1.0 / 3.0;
    return m;
  }();
  return P;
}

namespace {

FlowPoint material_point(const RigidPlasticInput& in, int q, double rate) {
  const double sy = std::isnan(in.yield[q]) ? in.law->yield(in.strain[q]) : in.yield[q];
  if (in.viscous_floor <= 0) {
    FlowPoint f = flow_point_at_yield(*in.law, sy, rate, in.epsdot_lim);
    if (in.regularization > 0) {
      const double c = in.regularization * sy;
      f.phi += 0.5 * c * rate * rate;
      f.sigma += c * rate;
      f.dsigma += c;
    }
    return f;
  }
  // Cold-start predictor: linear viscous everywhere, with the viscosity of
  // the material at the given rate.
  const double c = flow_point_at_yield(*in.law, sy, in.viscous_floor, in.epsdot_lim).sigma / in.viscous_floor;
  FlowPoint f;
  f.phi = 0.5 * c * rate * rate;
  f.sigma = c * rate;
  f.dsigma = c;
  f.rigid = true;
  return f;
}

// Volumetric rate row of a point's B: epsdot_v = b_v . v.
Vec8 volumetric_row(const Mat48& B) { return (B.row(0) + B.row(1) + B.row(2)).transpose(); }

// The element's Hessian by rows while it is summed: a row's eight entries
// are one vector, so each step below is one packed operation over them.
using RowHessian = Eigen::Matrix<double, 8, 8, Eigen::RowMajor>;

// A point's Hessian, H += s B^T P B + c g g^T, formed over B's structural
// zeros (quad4.cpp): node a's x column is (b, 0, h, c) = (dN/dx, 0, N/r,
// dN/dy), its y column (0, c, 0, b); P couples the normal rates among
// themselves and gamma with itself. Only the products that are not with a
// structural zero are formed, in the order the dense products sum them,
// so H is the dense products' to the bit (tests/unit: the element terms
// against the dense ones) for about two thirds of their operations. Each
// entry's operations are the same whether a row's entries are taken one
// by one or as a vector (coefficient-wise, no fused multiply-add). c = 0:
// the secant part alone.
void add_point_hessian(const Mat48& B, double s, double c, const Vec8& g, RowHessian& H) {
  const auto& P = effective_rate_metric();
  Eigen::Matrix<double, 4, 8, Eigen::RowMajor> PB;  // P B: rows e11, e22, e33, gamma
  for (int a = 0; a < 4; ++a) {
    const int x = 2 * a, y = x + 1;
    for (int k = 0; k < 3; ++k) {
      PB(k, x) = P(k, 0) * B(0, x) + P(k, 2) * B(2, x);
      PB(k, y) = P(k, 1) * B(1, y);
    }
    PB(3, x) = P(3, 3) * B(3, x);
    PB(3, y) = P(3, 3) * B(3, y);
  }
  // Each entry takes its secant term, then its rank-one term, in turn:
  // the sums of the two dense products added one after the other.
  const Eigen::Matrix<double, 1, 8> gt = g.transpose();
  for (int a = 0; a < 4; ++a) {
    const int x = 2 * a, y = x + 1;
    H.row(x) += s * ((B(0, x) * PB.row(0) + B(2, x) * PB.row(2)) + B(3, x) * PB.row(3));
    H.row(y) += s * (B(1, y) * PB.row(1) + B(3, y) * PB.row(3));
    if (c != 0) H.row(x) += (c * g(x)) * gt, H.row(y) += (c * g(y)) * gt;
  }
}

template <bool kGrad>
double accumulate(const RigidPlasticInput& in, Tangent t, ElementTerms* out) {
  const auto& P = effective_rate_metric();
  double energy = 0;
  RowHessian H;
  if constexpr (kGrad) {
    out->grad.setZero();
    H.setZero();
  }
  // The element's mean dilatation row, volume-weighted over the 2x2 points
  // (the volumetric penalty below), summed in the same loop.
  Vec8 bv = Vec8::Zero();
  double wc = 0;
  for (int q = 0; q < 4; ++q) {
    const Quad4Point p = quad4_gauss_point(in.X, q);
    const double w = volume_weight(p, in.geometry, 1.0);
    const Mat48 B = strain_rate_matrix(p, in.geometry);
    bv.noalias() += w * volumetric_row(B);
    wc += w;
    const Eigen::Vector4d eps = B * in.v;
    const Eigen::Vector4d Peps = P * eps;
    const double rate = std::sqrt(std::max(eps.dot(Peps), 0.0));
    const FlowPoint f = material_point(in, q, rate);
    energy += w * f.phi;
    if constexpr (kGrad) {
      // d phi/dv = (sigma/rate) B^T P eps; the Hessian adds
      // (sigma' / rate^2 - sigma / rate^3) (B^T P eps)(B^T P eps)^T, which is
      // identically zero in the linear-viscous (rigid) range.
      const double secant = f.rigid ? f.dsigma : f.sigma / rate;
      const Vec8 g = B.transpose() * Peps;
      out->grad.noalias() += w * secant * g;
      if (t == Tangent::None) continue;
      const bool consistent = t == Tangent::Consistent && !f.rigid;
      add_point_hessian(B, w * secant, consistent ? w * ((f.dsigma - secant) / (rate * rate)) : 0.0, g, H);
    }
  }
  // Volumetric penalty on the element's mean dilatation (Nagtegaal, Parks
  // and Rice 1974; Hughes 1980, "B-bar"): b_v averaged over the element
  // with the volume weights, (alpha/2) V (b_v . v)^2. For a parallelogram in
  // plane strain this is the 1-point rule; in axisymmetry the centre value
  // of v_r / r is not the element's mean, and the 1-point rule let two
  // blocks with non-matching meshes at a contact interface flow 6.9 %
  // non-uniformly under homogeneous compression (docs/decisions.md, "The
  // volumetric term on the element's mean dilatation").
  bv /= wc;
  const double ev = bv.dot(in.v);
  energy += 0.5 * in.alpha * wc * ev * ev;
  if constexpr (kGrad) {
    out->grad.noalias() += in.alpha * wc * ev * bv;
    out->hess = H;
    if (t != Tangent::None) out->hess.noalias() += in.alpha * wc * bv * bv.transpose();
    out->energy = energy;
  }
  return energy;
}

}  // namespace

double rigid_plastic_energy(const RigidPlasticInput& in) {
  return accumulate<false>(in, Tangent::Secant, nullptr);
}

void rigid_plastic_terms(const RigidPlasticInput& in, Tangent t, ElementTerms& out) {
  accumulate<true>(in, t, &out);
}

ElementPost rigid_plastic_post(const RigidPlasticInput& in) {
  const auto& P = effective_rate_metric();
  ElementPost post;
  double wsum = 0;
  Vec8 bv = Vec8::Zero();  // the mean dilatation row, as in accumulate
  post.min_detJ = INFINITY;
  for (int q = 0; q < 4; ++q) {
    const Quad4Point p = quad4_gauss_point(in.X, q);
    const double w = volume_weight(p, in.geometry, 1.0);
    const Mat48 B = strain_rate_matrix(p, in.geometry);
    bv.noalias() += w * volumetric_row(B);
    const Eigen::Vector4d eps = B * in.v;
    post.strain_rate[q] = std::sqrt(std::max(eps.dot(P * eps), 0.0));
    post.strain_rate_mean += w * post.strain_rate[q];
    wsum += w;
    post.min_detJ = std::min(post.min_detJ, p.detJ);
  }
  post.strain_rate_mean = wsum > 0 ? post.strain_rate_mean / wsum : 0.0;
  const Quad4Point c = quad4_point(in.X, 0.0, 0.0);
  post.min_detJ = std::min(post.min_detJ, c.detJ);
  post.volume = wsum;
  post.volumetric_rate = bv.dot(in.v) / wsum;
  post.mean_stress = in.alpha * post.volumetric_rate;  // sigma_m = alpha epsdot_v
  return post;
}

}  // namespace rpfem
