#include "curve_fit.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/types.hpp"
#include "curve_comparison.hpp"

namespace rpfem {

namespace {

const char* kLoadHeader = "stroke_mm,load_kN";
const char* kRingHeader = "reduction_percent,inner_diameter_change_percent";

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::string short_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

std::string TargetCurve::x_name() const { return kind == TargetKind::Ring ? "reduction_percent" : "stroke_mm"; }
std::string TargetCurve::y_name() const {
  return kind == TargetKind::Ring ? "inner_diameter_change_percent" : "load_kN";
}

TargetCurve read_target_curve(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such target file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot be read");
  TargetCurve t;
  t.file = path;
  std::string raw;
  std::getline(in, raw);
  std::string header;
  for (char c : trim(raw)) if (c != ' ' && c != '\t') header += c;
  if (header == kLoadHeader) t.kind = TargetKind::LoadStroke;
  else if (header == kRingHeader) t.kind = TargetKind::Ring;
  else
    throw InputError(path + ":1: expected the header '" + kLoadHeader + "' (a load-stroke table) or '" + kRingHeader +
                     "' (a ring calibration table), got '" + trim(raw) + "'");
  const std::string names[2] = {t.x_name(), t.y_name()};
  for (int line = 2; std::getline(in, raw); ++line) {
    if (trim(raw).empty()) continue;
    const std::string at = path + ":" + std::to_string(line) + ": ";
    std::vector<std::string> cells;
    std::stringstream ss(raw);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(trim(c));
    if (!raw.empty() && trim(raw).back() == ',') cells.push_back("");
    if (cells.size() != 2)
      throw InputError(at + "expected 2 comma-separated numbers (" + names[0] + "," + names[1] + "), got " +
                       std::to_string(cells.size()) + " cells");
    double v[2];
    for (int c = 0; c < 2; ++c) {
      char* end = nullptr;
      v[c] = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0' || !std::isfinite(v[c]))
        throw InputError(at + "column " + std::to_string(c + 1) + " (" + names[c] + "): expected a number, got '" +
                         cells[c] + "'");
    }
    const std::string col1 = "column 1 (" + names[0] + "): ";
    if (v[0] < 0) throw InputError(at + col1 + "expected a value >= 0, got " + cells[0]);
    if (!t.x.empty() && v[0] <= t.x.back())
      throw InputError(at + col1 + "expected a value above the previous row's " + short_number(t.x.back()) +
                       " (strictly increasing), got " + cells[0]);
    if (t.kind == TargetKind::Ring && v[0] >= 100)
      throw InputError(at + col1 + "expected a reduction below 100 %, got " + cells[0]);
    if (t.kind == TargetKind::LoadStroke && v[1] <= 0)
      throw InputError(at + "column 2 (load_kN): expected a positive load (the press load's magnitude, kN), got " +
                       cells[1]);
    t.x.push_back(v[0]);
    t.y.push_back(v[1]);
    t.line.push_back(line);
  }
  if (t.x.size() < 2)
    throw InputError(path + ": expected at least 2 data rows after the header, got " + std::to_string(t.x.size()));
  return t;
}

void require_within(const TargetCurve& t, double x_max, const std::string& why) {
  for (std::size_t i = 0; i < t.x.size(); ++i)
    if (t.x[i] > x_max * (1 + 1e-12))
      throw InputError(t.file + ":" + std::to_string(t.line[i]) + ": column 1 (" + t.x_name() + "): " +
                       short_number(t.x[i]) + " is beyond the simulated range, " + why);
}

double target_misfit(const TargetCurve& t, const std::vector<double>& sim_x, const std::vector<double>& sim_y) {
  if (sim_x.size() != sim_y.size() || sim_x.empty())
    throw std::invalid_argument("target_misfit: the simulated curve is empty or its columns differ in length");
  const double last = t.x.back();
  if (sim_x.back() < last - 1e-9 * std::max(1.0, std::abs(last)) || sim_x.front() > t.x.front() + 1e-9)
    throw std::invalid_argument("target_misfit: the simulated curve (" + short_number(sim_x.front()) + " to " +
                                short_number(sim_x.back()) + ") does not cover the target's " +
                                short_number(t.x.front()) + " to " + short_number(last));
  double sum = 0;
  for (std::size_t i = 0; i < t.x.size(); ++i) {
    const double d = interpolate_linear(sim_x, sim_y, t.x[i]) - t.y[i];
    const double r = t.kind == TargetKind::LoadStroke ? d / t.y[i] : d;
    sum += r * r;
  }
  return std::sqrt(sum / static_cast<double>(t.x.size()));
}

std::string misfit_definition(TargetKind kind) {
  return kind == TargetKind::LoadStroke
             ? "RMS over the target points of (F_sim - F_target) / F_target, F_sim the simulated load magnitude "
               "interpolated linearly in stroke at the target's strokes (relative)"
             : "RMS over the target points of (d_sim - d_target), d the inner-diameter change in %, d_sim "
               "interpolated linearly in height reduction at the target's reductions (percentage points)";
}

}  // namespace rpfem
