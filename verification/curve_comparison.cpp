#include "curve_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rpfem {

double interpolate_linear(const std::vector<double>& s, const std::vector<double>& F, double x) {
  const auto it = std::upper_bound(s.begin(), s.end(), x);
  if (it == s.begin()) return F.front();
  if (it == s.end()) return F.back();
  const std::size_t j = static_cast<std::size_t>(it - s.begin());
  const double t = (s[j] > s[j - 1]) ? (x - s[j - 1]) / (s[j] - s[j - 1]) : 1.0;
  return F[j - 1] + t * (F[j] - F[j - 1]);
}

CurveDifference curve_difference(const std::vector<double>& stroke_a, const std::vector<double>& load_a,
                                 const std::vector<double>& stroke_b, const std::vector<double>& load_b,
                                 double from, double stroke_tolerance) {
  if (stroke_a.size() != load_a.size() || stroke_b.size() != load_b.size() || stroke_b.size() < 2)
    throw std::invalid_argument("curve_difference: strokes and loads differ in length, or B has under 2 points");
  if (!std::is_sorted(stroke_b.begin(), stroke_b.end()))
    throw std::invalid_argument("curve_difference: B's strokes are not increasing");
  CurveDifference out;
  for (std::size_t i = 0; i < stroke_a.size(); ++i) {
    const double s = stroke_a[i];
    if (s < from || s > stroke_b.back() + 1e-12) continue;
    const double lo_s = s - stroke_tolerance, hi_s = s + stroke_tolerance;
    double lo = std::min(interpolate_linear(stroke_b, load_b, lo_s), interpolate_linear(stroke_b, load_b, hi_s));
    double hi = std::max(interpolate_linear(stroke_b, load_b, lo_s), interpolate_linear(stroke_b, load_b, hi_s));
    for (std::size_t j = 0; j < stroke_b.size(); ++j)
      if (stroke_b[j] > lo_s && stroke_b[j] < hi_s) lo = std::min(lo, load_b[j]), hi = std::max(hi, load_b[j]);
    const double F = load_a[i], ref = std::abs(interpolate_linear(stroke_b, load_b, s));
    const double d = F < lo ? lo - F : F > hi ? F - hi : 0.0;
    const double rel = ref > 0 ? d / ref : (d > 0 ? INFINITY : 0.0);
    if (rel > out.worst || out.points == 0) out.worst = std::max(out.worst, rel), out.at_stroke = s;
    ++out.points;
  }
  return out;
}

CurveDifference curve_jump(const std::vector<double>& stroke, const std::vector<double>& load, double from) {
  if (stroke.size() != load.size()) throw std::invalid_argument("curve_jump: stroke and load differ in length");
  CurveDifference out;
  for (std::size_t i = 1; i + 2 < stroke.size(); ++i) {
    if (stroke[i] < from || load[i + 1] == 0) continue;
    // The neighbouring steps' change per stroke, each weighted by its length
    // (a short step cut at a landing does not set the trend).
    const double ds = (stroke[i + 2] - stroke[i + 1]) + (stroke[i] - stroke[i - 1]);
    const double trend = ds > 0 ? ((load[i + 2] - load[i + 1]) + (load[i] - load[i - 1])) / ds : 0.0;
    const double jump = std::abs(load[i + 1] - load[i] - trend * (stroke[i + 1] - stroke[i])) / std::abs(load[i + 1]);
    ++out.points;
    if (!(jump <= out.worst)) out.worst = jump, out.at_stroke = stroke[i + 1];
  }
  return out;
}

}  // namespace rpfem
