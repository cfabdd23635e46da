#include "model/error_size_field.hpp"

#include <algorithm>
#include <cmath>

#include "mesh/error_indicator.hpp"

namespace rpfem {

namespace {

// The convergence rate of the strain rate (and of its error density) on
// bilinear quadrilaterals: O(h).
constexpr double kRate = 1;

// The element's planar area (shoelace over its four corners).
double area(const Mesh& m, const std::vector<Vec2>& x, Index e) {
  double a = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec2 &p = x[m.quads[e][i]], &q = x[m.quads[e][(i + 1) % 4]];
    a += p(0) * q(1) - q(0) * p(1);
  }
  return 0.5 * std::abs(a);
}

}  // namespace

ErrorSizes error_sizes(const Mesh& m, const std::vector<Vec2>& x, const std::vector<GaussValues>& rate, Geometry g,
                       const ErrorSizeRule& rule) {
  const StrainRateError z = strain_rate_error(m, x, rate, g);
  ErrorSizes out;
  out.relative = z.relative;
  const Index ne = m.num_elements();
  if (!(z.rate_norm > 0) || ne == 0) return out;
  // Li and Bettess (1995): the predicted count N and the error per new
  // element e_bar (error_size_field.hpp).
  const double allowed = rule.target * z.rate_norm;  // eta_bar ||epsdot_h||
  const double q = 1 / (kRate + 1);
  double sum = 0;
  for (double eta : z.element_eta) sum += std::pow(eta / allowed, 2 * q);
  out.predicted = std::pow(sum, (kRate + 1) / kRate);
  const double per_element = allowed / std::sqrt(std::max(out.predicted, 1.0));
  out.element.resize(ne);
  for (Index e = 0; e < ne; ++e) {
    const double eta = z.element_eta[e];
    const double h = eta > 0 ? std::sqrt(area(m, x, e)) * std::pow(per_element / eta, q) : rule.max_size;
    out.element[e] = std::clamp(h, rule.min_size, rule.max_size);
  }
  // At the nodes: the mean of the sizes of the elements around.
  std::vector<double> nodal(x.size(), 0.0), count(x.size(), 0.0);
  for (Index e = 0; e < ne; ++e)
    for (Index n : m.quads[e]) nodal[n] += out.element[e], count[n] += 1;
  for (std::size_t n = 0; n < nodal.size(); ++n) nodal[n] = count[n] > 0 ? nodal[n] / count[n] : rule.max_size;
  out.at = nodal_field(m, x, nodal);
  return out;
}

}  // namespace rpfem
