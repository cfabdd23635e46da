#include "analytic.hpp"

#include <cmath>

#include "core/types.hpp"

namespace rpfem {

double flow_stress(const FlowStressLaw& law, double eps, double rate) {
  return law.yield(eps) * (law.m == 0 ? 1.0 : std::pow(rate / law.rate_ref, law.m));
}

double upsetting_load_axisymmetric(const FlowStressLaw& law, double D0, double H0, double H, double rate) {
  const double A0 = kPi * D0 * D0 / 4;
  return flow_stress(law, std::log(H0 / H), rate) * A0 * H0 / H;
}

double upsetting_strain_plane_strain(double H0, double H) { return 2 / std::sqrt(3.0) * std::log(H0 / H); }

double upsetting_load_plane_strain(const FlowStressLaw& law, double w0, double H0, double H, double rate) {
  return 2 / std::sqrt(3.0) * flow_stress(law, upsetting_strain_plane_strain(H0, H), rate) * w0 * H0 / H;
}

}  // namespace rpfem

namespace rpfem {

double slab_upsetting_pressure_ratio(double m, double R, double H) {
  return 1 + 2 * m * R / (3 * std::sqrt(3.0) * H);
}

double ring_inner_diameter_change_frictionless(double H0, double H) { return std::sqrt(H0 / H) - 1; }

}  // namespace rpfem
