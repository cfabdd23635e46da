#include "homogeneous_flow.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "results.hpp"

namespace rpfem {

HomogeneousFlowError homogeneous_flow_error(const std::string& h5, int step, double platen_speed, Geometry g) {
  char group[32];
  std::snprintf(group, sizeof group, "/steps/%06d/", step);
  const std::string s(group);
  const auto x = read_h5_dataset(h5, s + "coordinates");
  const auto vel = read_h5_dataset(h5, s + "velocity");
  const auto rate = read_h5_dataset(h5, s + "strain_rate");
  if (x.empty() || rate.empty() || !(platen_speed > 0))
    throw std::runtime_error(h5 + ": no mesh or platen speed for the homogeneous flow at step " + std::to_string(step));
  double ymin = INFINITY, ymax = -INFINITY;
  for (std::size_t i = 1; i < x.size(); i += 2) ymin = std::min(ymin, x[i]), ymax = std::max(ymax, x[i]);
  HomogeneousFlowError out;
  out.height = ymax - ymin;
  const bool axi = g == Geometry::Axisymmetric;
  out.exact_rate = (axi ? 1.0 : 2.0 / std::sqrt(3.0)) * platen_speed / out.height;
  double d2 = 0, n2 = 0;
  for (double e : rate) {
    out.strain_rate = std::max(out.strain_rate, std::abs(e / out.exact_rate - 1));
    d2 += std::pow(e - out.exact_rate, 2), n2 += out.exact_rate * out.exact_rate;
    ++out.elements;
  }
  out.strain_rate_l2 = std::sqrt(d2 / n2);
  if (axi)
    for (std::size_t i = 0; 2 * i + 1 < x.size(); ++i) {
      const Vec2 exact(platen_speed * x[2 * i] / (2 * out.height), -platen_speed * (x[2 * i + 1] - ymin) / out.height);
      const Vec2 v(vel[2 * i], vel[2 * i + 1]);
      out.velocity = std::max(out.velocity, (v - exact).norm() / platen_speed);
    }
  return out;
}

}  // namespace rpfem
