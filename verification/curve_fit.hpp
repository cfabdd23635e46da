// Calibration targets (`rpfem calibrate`): a measured curve read from CSV
// that a run should reproduce, and the misfit of a simulated curve to it.
//
//   stroke_mm,load_kN                                  a load-stroke table
//   reduction_percent,inner_diameter_change_percent    a ring calibration table
//
// The header is one of the two lines above; then at least 2 rows of two
// finite numbers, the abscissa >= 0 and strictly increasing, loads > 0 (the
// press load's magnitude), reductions below 100 %. Blank lines are skipped.
#pragma once
#include <string>
#include <vector>

namespace rpfem {

enum class TargetKind { LoadStroke, Ring };

struct TargetCurve {
  std::string file;
  TargetKind kind = TargetKind::LoadStroke;
  std::vector<double> x;  // stroke (mm) or height reduction (%)
  std::vector<double> y;  // load (kN) or inner-diameter change (%)
  std::vector<int> line;  // the file's line of each point (1: the header)
  std::string x_name() const;  // the header's column names
  std::string y_name() const;
};

// Throws InputError naming the file, the line and column, and what was
// expected.
TargetCurve read_target_curve(const std::string& path);

// Throws InputError naming the first point beyond x_max (the simulated
// range; `why` says where x_max comes from).
void require_within(const TargetCurve& target, double x_max, const std::string& why);

// The simulated curve (sim_x increasing, in the target's units) interpolated
// linearly at the target's abscissae; over the N points,
//   load-stroke: sqrt(1/N sum ((F_sim(x_i) - F_i) / F_i)^2)  (relative)
//   ring:        sqrt(1/N sum (d_sim(x_i) - d_i)^2)        (percentage points)
// Throws std::invalid_argument if the simulated curve does not reach the
// target's last abscissa (within 1e-9 of it).
double target_misfit(const TargetCurve& target, const std::vector<double>& sim_x, const std::vector<double>& sim_y);
// The definition above in words, for the output.
std::string misfit_definition(TargetKind kind);

}  // namespace rpfem
