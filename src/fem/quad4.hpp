// 4-node isoparametric quadrilateral: shape functions, Jacobian, and the
// strain-rate matrix B with rows (e_11, e_22, e_33, gamma_12), where e_33 is
// the hoop rate v_r / r in axisymmetry and 0 in plane strain
// (Kobayashi, Oh, Altan 1989, eq. 7.29-7.31).
#pragma once
#include <array>

#include <Eigen/Core>

#include "core/types.hpp"

namespace rpfem {

using Quad4Coords = std::array<Vec2, 4>;
using Mat48 = Eigen::Matrix<double, 4, 8>;
using Vec8 = Eigen::Matrix<double, 8, 1>;
using Mat8 = Eigen::Matrix<double, 8, 8>;

struct Quad4Point {
  Eigen::Vector4d N;                 // shape functions
  Eigen::Matrix<double, 4, 2> dN;    // dN/dx (physical)
  double detJ = 0;
  double radius = 0;                 // x_0 at the point (r in axisymmetry)
};

// 2x2 Gauss points (+-1/sqrt 3, weight 1) in the order of the element's
// nodes; the 1-point rule is (0, 0) with weight 4.
inline constexpr double kGauss2 = 0.57735026918962576451;
inline constexpr std::array<std::array<double, 2>, 4> kGaussPoints2x2{
    {{-kGauss2, -kGauss2}, {kGauss2, -kGauss2}, {kGauss2, kGauss2}, {-kGauss2, kGauss2}}};

Quad4Point quad4_point(const Quad4Coords& X, double xi, double eta);
// The same at the 2x2 point kGaussPoints2x2[q], the parent element's shape
// functions tabulated once: the same bits as quad4_point there.
Quad4Point quad4_gauss_point(const Quad4Coords& X, int q);
// The shape functions alone at (xi, eta), nodes counter-clockwise from
// (-1, -1).
Eigen::Vector4d quad4_shape(double xi, double eta);

// Strain-rate matrix; eps = B * v with v = (v1x, v1y, v2x, v2y, ...).
Mat48 strain_rate_matrix(const Quad4Point& p, Geometry g);

// Integration weight of a point with parametric weight w: w detJ, times
// 2 pi r in axisymmetry (volume of the ring), per unit depth in plane strain.
inline double volume_weight(const Quad4Point& p, Geometry g, double w) {
  return g == Geometry::Axisymmetric ? 2.0 * kPi * p.radius * p.detJ * w : p.detJ * w;
}

}  // namespace rpfem
