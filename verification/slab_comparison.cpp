#include "slab_comparison.hpp"

#include <cmath>

#include "analytic.hpp"
#include "core/types.hpp"

namespace rpfem {

std::vector<SlabRow> slab_comparison(const History& h, const std::string& die, const FlowStressLaw& law, double m,
                                     double R0, double H0, double height_per_stroke) {
  const auto& stroke = h.at("stroke");
  const auto& area = h.at(die + ".contact_area");
  const auto& pressure = h.at(die + ".mean_pressure");
  const auto& fy = h.at(die + ".Fy");
  std::vector<SlabRow> rows;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    SlabRow r;
    r.stroke = stroke[i];
    r.height = H0 - height_per_stroke * stroke[i];
    r.flow_stress = flow_stress(law, std::log(H0 / r.height), 1.0);
    r.contact_radius = std::sqrt(area[i] / kPi);
    r.homogeneous_radius = R0 * std::sqrt(H0 / r.height);  // volume conserved
    r.pressure = pressure[i];
    r.slab_pressure = r.flow_stress * slab_upsetting_pressure_ratio(m, r.contact_radius, r.height);
    r.load = std::abs(fy[i]);
    r.slab_load = r.flow_stress * slab_upsetting_pressure_ratio(m, r.homogeneous_radius, r.height) * kPi *
                  r.homogeneous_radius * r.homogeneous_radius;
    rows.push_back(r);
  }
  return rows;
}

}  // namespace rpfem
