#include "fem/quad4.hpp"

#include <Eigen/LU>

namespace rpfem {

namespace {
constexpr double sx[4] = {-1, 1, 1, -1};
constexpr double sy[4] = {-1, -1, 1, 1};
}  // namespace

Eigen::Vector4d quad4_shape(double xi, double eta) {
  Eigen::Vector4d N;
  for (int a = 0; a < 4; ++a) N(a) = 0.25 * (1 + sx[a] * xi) * (1 + sy[a] * eta);
  return N;
}

namespace {

using ShapeDerivatives = Eigen::Matrix<double, 4, 2>;  // dN_a / d(xi, eta)

ShapeDerivatives shape_derivatives(double xi, double eta) {
  ShapeDerivatives dNdxi;
  for (int a = 0; a < 4; ++a) {
    dNdxi(a, 0) = 0.25 * sx[a] * (1 + sy[a] * eta);
    dNdxi(a, 1) = 0.25 * sy[a] * (1 + sx[a] * xi);
  }
  return dNdxi;
}

// The point's values from the parent element's shape functions and their
// derivatives at it (eq. 7.29-7.31).
Quad4Point map_point(const Quad4Coords& X, const Eigen::Vector4d& N, const ShapeDerivatives& dNdxi) {
  Quad4Point p;
  p.N = N;
  Eigen::Matrix2d J = Eigen::Matrix2d::Zero();  // J_ij = d x_j / d xi_i
  for (int a = 0; a < 4; ++a) {
    J(0, 0) += dNdxi(a, 0) * X[a](0);
    J(0, 1) += dNdxi(a, 0) * X[a](1);
    J(1, 0) += dNdxi(a, 1) * X[a](0);
    J(1, 1) += dNdxi(a, 1) * X[a](1);
    p.radius += p.N(a) * X[a](0);
  }
  p.detJ = J.determinant();
  const Eigen::Matrix2d Jinv = J.inverse();
  p.dN = dNdxi * Jinv.transpose();
  return p;
}

// The parent element's values at the 2x2 points, computed once by the very
// functions quad4_point calls (so a Gauss point's values are its bits).
struct GaussTable {
  std::array<Eigen::Vector4d, 4> N;
  std::array<ShapeDerivatives, 4> dNdxi;
  GaussTable() {
    for (int q = 0; q < 4; ++q) {
      N[q] = quad4_shape(kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
      dNdxi[q] = shape_derivatives(kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
    }
  }
};
const GaussTable kGaussTable;

}  // namespace

Quad4Point quad4_point(const Quad4Coords& X, double xi, double eta) {
  return map_point(X, quad4_shape(xi, eta), shape_derivatives(xi, eta));
}

Quad4Point quad4_gauss_point(const Quad4Coords& X, int q) {
  return map_point(X, kGaussTable.N[q], kGaussTable.dNdxi[q]);
}

Mat48 strain_rate_matrix(const Quad4Point& p, Geometry g) {
  Mat48 B = Mat48::Zero();
  for (int a = 0; a < 4; ++a) {
    B(0, 2 * a) = p.dN(a, 0);
    B(1, 2 * a + 1) = p.dN(a, 1);
    if (g == Geometry::Axisymmetric) B(2, 2 * a) = p.N(a) / p.radius;  // hoop v_r / r
    B(3, 2 * a) = p.dN(a, 1);
    B(3, 2 * a + 1) = p.dN(a, 0);
  }
  return B;
}

}  // namespace rpfem
