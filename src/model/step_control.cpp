#include "model/step_control.hpp"

#include <algorithm>
#include <cmath>

#include "fem/quad4.hpp"

namespace rpfem {

namespace {

// Element e's volume at x + dt v (2x2 Gauss).
double moved_volume(const Mesh& m, Geometry g, const std::vector<Vec2>& x, double dt, const std::vector<Vec2>& v,
                    Index e) {
  Quad4Coords X;
  for (int a = 0; a < 4; ++a) X[a] = x[m.quads[e][a]] + dt * v[m.quads[e][a]];
  double vol = 0;
  for (int q = 0; q < 4; ++q) vol += volume_weight(quad4_gauss_point(X, q), g, 1.0);
  return vol;
}

}  // namespace

double step_error_estimate(const Mesh& m, Geometry g, const std::vector<Vec2>& x, double dt,
                           const std::vector<Vec2>& v0, const std::vector<Vec2>& v_half,
                           const std::vector<std::array<double, 4>>& eps,
                           const std::vector<std::array<double, 4>>& rate0,
                           const std::vector<std::array<double, 4>>& rate_half,
                           const std::vector<ElementMaterial>& material, double length) {
  double motion = 0;
  for (std::size_t i = 0; i < v0.size(); ++i) motion = std::max(motion, dt * (v_half[i] - v0[i]).norm() / length);
  // The flow stress times the volume summed over the elements, a load's
  // measure: the relative error of the sum, bounded by the volume-weighted
  // mean of the elements' relative errors.
  double err = 0, total = 0;
  for (Index k = 0; k < m.num_elements(); ++k) {
    const double vm = moved_volume(m, g, x, dt, v_half, k), ve = moved_volume(m, g, x, dt, v0, k);
    double sm_mean = 0, ds_mean = 0;
    for (int q = 0; q < 4; ++q) {
      const double sm = material[k].law->yield(eps[k][q] + dt * rate_half[k][q]);
      const double se = material[k].law->yield(eps[k][q] + dt * rate0[k][q]);
      sm_mean += 0.25 * sm, ds_mean += 0.25 * std::abs(sm - se);
    }
    err += ds_mean * vm + sm_mean * std::abs(vm - ve);
    total += sm_mean * vm;
  }
  return std::max(motion, total > 0 ? err / total : 0.0);
}

double next_increment(double ds, double estimate, double bound, double base, bool rejected,
                      const StepControlFactors& f) {
  // q = 1 in (2): the exponent of the error per unit step.
  const double proposed = estimate > 0 ? ds * f.safety * bound / estimate : INFINITY;
  return std::clamp(proposed, f.fac_min * base, (rejected ? 1.0 : f.fac_max) * base);
}

}  // namespace rpfem
