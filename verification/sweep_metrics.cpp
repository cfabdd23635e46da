#include "sweep_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "curve_comparison.hpp"

namespace rpfem {

RunMetrics run_metrics(const History& h, const std::string& load) {
  RunMetrics m;
  const std::size_t n = h.rows();
  if (n == 0) return m;
  m.steps = static_cast<int>(n) - 1;
  m.final_stroke = h.at("stroke").back();
  m.final_load = std::abs(h.at(load).back()) / 1e3;
  auto has = [&](const std::string& c) { return h.data.count(c) > 0; };
  if (has("max_penetration_rel"))
    for (double p : h.at("max_penetration_rel")) m.penetration = std::max(m.penetration, p);
  for (double dv : h.at("volume_change")) m.volume_error = std::max(m.volume_error, std::abs(dv));
  auto median = [](std::vector<double> x) {
    std::sort(x.begin(), x.end());
    const std::size_t k = x.size() / 2;
    return x.size() % 2 ? x[k] : 0.5 * (x[k - 1] + x[k]);
  };
  std::vector<double> it(h.at("newton_iterations").begin() + 1, h.at("newton_iterations").end());
  if (!it.empty()) {
    for (double k : it) m.iterations_mean += k / it.size(), m.iterations_max = std::max(m.iterations_max, k);
    m.iterations_median = median(it);
    if (has("solves")) {
      std::vector<double> per(it.size());
      for (std::size_t i = 0; i < it.size(); ++i) per[i] = it[i] / std::max(1.0, h.at("solves")[i + 1]);
      m.iterations_per_solve_median = median(per);
    }
  }
  if (has("tangent_rcond"))
    for (double r : h.at("tangent_rcond"))
      if (r > 0) m.rcond = m.rcond < 0 ? r : std::min(m.rcond, r);
  return m;
}

LoadError load_error(const History& run, const History& ref, const std::string& load, double from) {
  LoadError e;
  if (run.rows() < 2 || ref.rows() < 2) return e;
  const auto& s = run.at("stroke");
  const CurveDifference d = curve_difference(s, run.at(load), ref.at("stroke"), ref.at(load), from, 0.0);
  if (d.points > 0) e.largest = d.worst;
  const CurveDifference last = curve_difference({s.back()}, {run.at(load).back()}, ref.at("stroke"), ref.at(load),
                                                0.0, 0.0);
  if (last.points > 0) e.final = last.worst;
  return e;
}

double mean_load(const History& h, const std::string& load, double from) {
  const auto& s = h.at("stroke");
  const auto& f = h.at(load);
  double work = 0;  // kN mm
  for (std::size_t i = 1; i < s.size(); ++i) {
    if (s[i] <= from) continue;
    const double a = std::max(s[i - 1], from), t = s[i] > s[i - 1] ? (a - s[i - 1]) / (s[i] - s[i - 1]) : 0.0;
    const double fa = std::abs(f[i - 1] + t * (f[i] - f[i - 1])), fb = std::abs(f[i]);
    work += 0.5 * (fa + fb) / 1e3 * (s[i] - a);
  }
  return !s.empty() && s.back() > from ? work / (s.back() - from) : -1.0;
}

Richardson richardson(std::vector<double> h, std::vector<double> f) {
  Richardson r;
  if (h.size() != f.size() || h.size() < 3) {
    r.note = "needs three runs or more";
    return r;
  }
  std::vector<std::size_t> idx(h.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return h[a] < h[b]; });
  const double h1 = h[idx[0]], h2 = h[idx[1]], h3 = h[idx[2]];
  const double f1 = f[idx[0]], f2 = f[idx[1]], f3 = f[idx[2]];
  r.ratio = h2 / h1;
  if (!(h1 > 0) || std::abs(h3 / h2 / r.ratio - 1) > 1e-6 || !(r.ratio > 1)) {
    r.note = "the three finest sizes need a constant ratio above 1";
    return r;
  }
  const double d21 = f2 - f1, d32 = f3 - f2;
  if (d21 == 0 || d32 / d21 <= 1) {
    r.note = "the differences do not shrink monotonically (not in the asymptotic range)";
    return r;
  }
  r.order = std::log(d32 / d21) / std::log(r.ratio);
  r.extrapolated = f1 - d21 / (std::pow(r.ratio, r.order) - 1);
  r.ok = std::isfinite(r.order) && std::isfinite(r.extrapolated);
  if (!r.ok) r.note = "non-finite estimate";
  return r;
}

}  // namespace rpfem
