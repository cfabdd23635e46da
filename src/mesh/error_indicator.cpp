#include "mesh/error_indicator.hpp"

#include <cmath>

#include "fem/quad4.hpp"
#include "mesh/field_transfer.hpp"

namespace rpfem {

StrainRateError strain_rate_error(const Mesh& m, const std::vector<Vec2>& x,
                                  const std::vector<std::array<double, 4>>& rate, Geometry g) {
  const std::vector<double> nodal = recover_at_nodes(m, x, rate);
  StrainRateError out;
  const Index ne = m.num_elements();
  out.element_rms.assign(ne, 0.0);
  out.element_eta.assign(ne, 0.0);
  double err2 = 0, ref2 = 0;
  for (Index e = 0; e < ne; ++e) {
    Quad4Coords X;
    for (int a = 0; a < 4; ++a) X[a] = x[m.quads[e][a]];
    double eta2 = 0, vol = 0;
    for (int q = 0; q < 4; ++q) {
      const Quad4Point p = quad4_gauss_point(X, q);
      const double w = volume_weight(p, g, 1.0);
      double star = 0;
      for (int a = 0; a < 4; ++a) star += p.N(a) * nodal[m.quads[e][a]];
      const double d = star - rate[e][q];
      eta2 += w * d * d;
      ref2 += w * rate[e][q] * rate[e][q];
      vol += w;
    }
    err2 += eta2;
    out.element_eta[e] = std::sqrt(eta2);
    out.element_rms[e] = vol > 0 ? std::sqrt(eta2 / vol) : 0.0;
  }
  out.rate_norm = std::sqrt(ref2);
  out.relative = ref2 > 0 ? std::sqrt(err2 / ref2) : 0.0;
  return out;
}

}  // namespace rpfem
