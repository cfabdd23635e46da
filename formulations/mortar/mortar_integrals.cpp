#include "mortar/mortar_integrals.hpp"

#include <algorithm>
#include <cmath>

namespace rpfem {

namespace {

// Parameters within this of an edge's ends count as its ends (a master node
// on a slave node's normal line).
constexpr double kEndTolerance = 1e-9;

}  // namespace

std::optional<double> project_onto_slave(const Vec2& xa, const Vec2& xb, const Vec2& na, const Vec2& nb,
                                         const Vec2& p) {
  // (q + xi d) x (na + xi dn) = c0 + c1 xi + c2 xi^2 = 0, q = xa - p.
  const Vec2 d = xb - xa, dn = nb - na, q = xa - p;
  const double c0 = cross(q, na), c1 = cross(q, dn) + cross(d, na), c2 = cross(d, dn);
  const double scale = d.norm();
  if (std::abs(c2) <= 1e-12 * scale) {
    if (std::abs(c1) <= 1e-14 * scale) return std::nullopt;
    return -c0 / c1;
  }
  const double disc = c1 * c1 - 4 * c2 * c0;
  if (disc < 0) return std::nullopt;
  // The numerically stable pair of roots; the one on the edge, else the one
  // whose point is nearer p. The other is where the interpolated normal,
  // extrapolated, has turned to point at p: a master node on the slave
  // edge's own line (a flat die touching a flat face whose end node's
  // normal a corner tilts) has its true root at its own place on the line,
  // far off the edge, and a false one where the normal has turned parallel
  // to the line.
  const double s = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
  const double r1 = s / c2, r2 = s != 0 ? c0 / s : r1;
  const auto distance = [&](double xi) { return (q + xi * d).norm(); };
  const auto on_edge = [](double xi) { return xi >= -kEndTolerance && xi <= 1 + kEndTolerance; };
  if (on_edge(r1) != on_edge(r2)) return on_edge(r1) ? r1 : r2;
  return distance(r1) <= distance(r2) ? r1 : r2;
}

std::optional<double> project_onto_master(const Vec2& xA, const Vec2& xB, const Vec2& n, const Vec2& p) {
  const Vec2 d = xB - xA;
  const double den = cross(d, n);
  if (std::abs(den) <= 1e-12 * d.norm()) return std::nullopt;
  return cross(p - xA, n) / den;
}

std::optional<MortarPiece> mortar_piece(const Vec2& xa, const Vec2& xb, const Vec2& na, const Vec2& nb,
                                        const Vec2& xA, const Vec2& xB) {
  // The slave nodes onto the master's line: the part of the master edge
  // the slave edge's normals sweep over is [eta_a, eta_b] (or reversed).
  const auto eta_a = project_onto_master(xA, xB, na, xa), eta_b = project_onto_master(xA, xB, nb, xb);
  if (!eta_a || !eta_b || *eta_a == *eta_b) return std::nullopt;
  const auto inside = [](double e) { return e >= -kEndTolerance && e <= 1 + kEndTolerance; };
  // An end of the piece: the slave node where it projects onto the master
  // edge, else the master node the sweep passes (eta 0 or 1), projected
  // back onto the slave edge. Only a master node inside the sweep is
  // projected: one far outside it may have no projection at all.
  const auto end = [&](double eta_node, double xi_node, double& xi, double& eta) {
    if (inside(eta_node)) {
      xi = xi_node, eta = std::clamp(eta_node, 0.0, 1.0);
      return true;
    }
    eta = eta_node < 0 ? 0.0 : 1.0;
    const auto r = project_onto_slave(xa, xb, na, nb, eta == 0 ? xA : xB);
    if (!r) return false;
    xi = *r;
    return true;
  };
  // Both slave nodes off the master edge on the same side: no overlap.
  if ((*eta_a < 0 && *eta_b < 0) || (*eta_a > 1 && *eta_b > 1)) return std::nullopt;
  MortarPiece p;
  if (!end(*eta_a, 0.0, p.xi0, p.eta0) || !end(*eta_b, 1.0, p.xi1, p.eta1)) return std::nullopt;
  if (!(p.xi0 >= -kEndTolerance && p.xi1 <= 1 + kEndTolerance)) return std::nullopt;
  p.xi0 = std::clamp(p.xi0, 0.0, 1.0), p.xi1 = std::clamp(p.xi1, 0.0, 1.0);
  if (!(p.xi1 - p.xi0 > kEndTolerance)) return std::nullopt;
  return p;
}

std::optional<MortarPiece> clip_piece(const MortarPiece& p, double f0, double f1, double lo, double hi) {
  // t in [0, 1] along the piece, f(t) = f0 + t (f1 - f0).
  double t0 = 0, t1 = 1;
  const double df = f1 - f0;
  if (df == 0) {
    if (f0 < lo || f0 > hi) return std::nullopt;
  } else {
    const double a = (lo - f0) / df, b = (hi - f0) / df;  // where f crosses lo and hi
    t0 = std::max(t0, std::min(a, b)), t1 = std::min(t1, std::max(a, b));
  }
  MortarPiece q = p;
  const double dxi = p.xi1 - p.xi0, deta = p.eta1 - p.eta0;
  q.xi0 = p.xi0 + t0 * dxi, q.xi1 = p.xi0 + t1 * dxi;
  q.eta0 = p.eta0 + t0 * deta, q.eta1 = p.eta0 + t1 * deta;
  if (!(q.xi1 - q.xi0 > kEndTolerance)) return std::nullopt;
  return q;
}

std::optional<MortarPiece> clip_to_slab(const MortarPiece& p, const Vec2& xa, const Vec2& xb, const Vec2& xA,
                                        const Vec2& xB) {
  // s(xi) = (x(xi) - xA) . (xB - xA) / |xB - xA|^2, in [0, 1] on the slab.
  const Vec2 tm = (xB - xA) / (xB - xA).squaredNorm();
  const auto s = [&](double xi) { return (xa + xi * (xb - xa) - xA).dot(tm); };
  return clip_piece(p, s(p.xi0), s(p.xi1), 0.0, 1.0);
}

Mat22 dual_coefficients(const Mat22& Mc) {
  // det / trace^2 is 3/16 for an interval in plane strain and 1/8 for one
  // starting on the axis; below kSliver Mc is singular to round-off (an
  // interval of zero length or weight).
  constexpr double kSliver = 1e-4;
  const double det = Mc[0][0] * Mc[1][1] - Mc[0][1] * Mc[1][0];
  const double trace = Mc[0][0] + Mc[1][1];
  if (!(trace > 0) || !(det > kSliver * trace * trace)) return Mat22{{{1, 0}, {0, 1}}};
  const double Dc[2] = {Mc[0][0] + Mc[0][1], Mc[1][0] + Mc[1][1]};
  // A = diag(D_c) Mc^-1.
  return Mat22{{{Dc[0] * Mc[1][1] / det, -Dc[0] * Mc[0][1] / det}, {-Dc[1] * Mc[1][0] / det, Dc[1] * Mc[0][0] / det}}};
}

namespace {

// The 2-point Gauss rule over a piece (exact for the integrands here, of
// degree 3 at most): f(xi, eta, w) at each point, w the weight of
// integrate_piece.
template <class F>
void for_each_point(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, F&& f) {
  const double L = (xb - xa).norm(), J = p.xi1 - p.xi0;
  constexpr double kGauss = 0.5773502691896257;  // 1 / sqrt 3: the 2-point rule on [-1, 1]
  for (const double s : {-kGauss, kGauss}) {
    const double t = 0.5 * (1 + s);  // in [0, 1] along the piece
    const double xi = p.xi0 + t * J, eta = p.eta0 + t * (p.eta1 - p.eta0);
    const double r = (1 - xi) * xa(0) + xi * xb(0);
    f(xi, eta, 0.5 * J * L * (g == Geometry::Axisymmetric ? 2 * kPi * r : 1.0));
  }
}

}  // namespace

std::array<double, 2> TestBasis::at(double xi) const {
  const double s = (xi - lo) / (hi - lo);
  return {C[0][0] * (1 - s) + C[0][1] * s, C[1][0] * (1 - s) + C[1][1] * s};
}

void add_interval_mass(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, double lo, double hi,
                       Mat22& ML) {
  for_each_point(xa, xb, g, p, [&](double xi, double, double w) {
    const double s = (xi - lo) / (hi - lo);
    const std::array<double, 2> L{1 - s, s};
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) ML[k][l] += L[k] * L[l] * w;
  });
}

void integrate_piece(const Vec2& xa, const Vec2& xb, Geometry g, const MortarPiece& p, Mat22& D, Mat22& M,
                     const TestBasis* test) {
  for_each_point(xa, xb, g, p, [&](double xi, double eta, double w) {
    const std::array<double, 2> N{1 - xi, xi}, NM{1 - eta, eta};
    const std::array<double, 2> phi = test ? test->at(xi) : N;  // the rows' test functions
    for (int k = 0; k < 2; ++k)
      for (int l = 0; l < 2; ++l) D[k][l] += phi[k] * N[l] * w, M[k][l] += phi[k] * NM[l] * w;
  });
}

}  // namespace rpfem
