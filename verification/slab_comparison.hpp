// Upsetting with friction against the slab method, step by step, from a
// run's history.csv (the die's load, contact area and mean pressure).
#pragma once
#include <string>
#include <vector>

#include "material/flow_stress.hpp"
#include "results.hpp"

namespace rpfem {

struct SlabRow {
  double stroke = 0;             // mm of die travel
  double height = 0;             // mm, full height H
  double flow_stress = 0;        // MPa, sigma_bar at the homogeneous strain ln(H0/H)
  double contact_radius = 0;     // mm, sqrt(A/pi) of the computed contact area
  double homogeneous_radius = 0; // mm, R0 sqrt(H0/H)
  double pressure = 0;           // MPa, computed mean die pressure
  double slab_pressure = 0;      // MPa, slab estimate at the computed contact radius
  double load = 0;               // N, computed
  double slab_load = 0;          // N, slab estimate at the homogeneous radius
};

// Axisymmetric cylinder of radius R0 and full height H0 with friction factor
// m; the history's stroke is the travel of die `die` and the full height is
// H0 - height_per_stroke * stroke (2 for a half model pressed by one die).
std::vector<SlabRow> slab_comparison(const History& h, const std::string& die, const FlowStressLaw& law, double m,
                                     double R0, double H0, double height_per_stroke);

}  // namespace rpfem
