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

std::vector<std::size_t> landing_steps(const History& h) {
  std::vector<std::size_t> l;
  if (!h.data.count("contact_nodes")) return l;
  const auto& c = h.at("contact_nodes");
  for (std::size_t i = 1; i < c.size(); ++i)
    if (c[i] != c[i - 1]) l.push_back(i);
  return l;
}

double max_relative_load_error(const History& run, const History& ref, const std::string& load) {
  if (run.rows() == 0 || ref.rows() == 0) return -1;
  const auto &rs = ref.at("stroke"), &rF = ref.at(load), &s = run.at("stroke"), &F = run.at(load);
  // The stroke windows around each landing: one step either side.
  std::vector<std::pair<double, double>> windows;
  for (const History* h : {&ref, &run}) {
    const auto& hs = h->at("stroke");
    for (std::size_t i : landing_steps(*h)) windows.push_back({hs[i - 1], hs[std::min(i + 1, hs.size() - 1)]});
  }
  std::vector<double> ref_abs(rF.size());
  double largest = 0;
  for (std::size_t i = 0; i < rF.size(); ++i) ref_abs[i] = std::abs(rF[i]), largest = std::max(largest, ref_abs[i]);
  double worst = -1;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double lo = s[i == 0 ? 0 : i - 1], hi = s[std::min(i + 1, s.size() - 1)];
    const bool near = std::any_of(windows.begin(), windows.end(),
                                  [&](const std::pair<double, double>& w) { return w.first <= hi && w.second >= lo; });
    if (!near) worst = std::max(worst, std::abs(std::abs(F[i]) - interpolate_linear(rs, ref_abs, s[i])));
  }
  return worst >= 0 && largest > 0 ? worst / largest : -1.0;
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

LoadError column_difference(const History& run, const History& ref, const std::string& column, double from) {
  LoadError e;
  if (run.rows() < 2 || ref.rows() < 2) return e;
  const auto &s = run.at("stroke"), &v = run.at(column), &rs = ref.at("stroke"), &rv = ref.at(column);
  // Strokes past the reference's last are not compared (as curve_difference).
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i] >= from && s[i] <= rs.back() + 1e-12)
      e.largest = std::max(e.largest, std::abs(v[i] - interpolate_linear(rs, rv, s[i])));
  if (s.back() <= rs.back() + 1e-12) e.final = std::abs(v.back() - interpolate_linear(rs, rv, s.back()));
  return e;
}

double mean_load_error(const History& run, const History& ref, const std::string& load, double from) {
  if (run.rows() < 2 || ref.rows() < 2) return -1;
  const double end = run.at("stroke").back();
  if (ref.at("stroke").back() < end - 1e-12) return -1;
  // The reference's history up to the run's last stroke, its last point interpolated there.
  History cut;
  const auto& rs = ref.at("stroke");
  std::size_t n = 0;
  while (n < rs.size() && rs[n] < end - 1e-12) ++n;
  for (const std::string& c : {std::string("stroke"), load}) {
    std::vector<double> col(ref.at(c).begin(), ref.at(c).begin() + static_cast<long>(n));
    col.push_back(c == "stroke" ? end : interpolate_linear(rs, ref.at(c), end));
    cut.data[c] = col;
  }
  const double m = mean_load(run, load, from), mr = mean_load(cut, load, from);
  return m >= 0 && mr > 0 ? std::abs(m / mr - 1) : -1.0;
}

ObservedOrders observed_orders(std::vector<double> a, std::vector<double> e, double floor) {
  ObservedOrders o;
  std::vector<std::size_t> idx(std::min(a.size(), e.size()));
  std::iota(idx.begin(), idx.end(), 0);
  std::sort(idx.begin(), idx.end(), [&](std::size_t i, std::size_t j) { return a[i] > a[j]; });
  for (std::size_t i : idx) o.a.push_back(a[i]), o.e.push_back(e[i]);
  const std::size_t n = o.a.size();
  auto usable = [&](std::size_t k) { return o.a[k] > 0 && o.e[k] > floor && o.e[k] > 0; };
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const bool m = usable(k) && usable(k + 1) && o.a[k] > o.a[k + 1];
    o.successive.push_back(m ? std::log(o.e[k] / o.e[k + 1]) / std::log(o.a[k] / o.a[k + 1]) : 0.0);
    o.successive_measured.push_back(m);
  }
  // Least squares: p = sum (x - xm)(y - ym) / sum (x - xm)^2, x = ln a, y = ln e.
  std::vector<double> x, y;
  for (std::size_t k = 0; k < n; ++k)
    if (usable(k)) x.push_back(std::log(o.a[k])), y.push_back(std::log(o.e[k]));
  const double xm = x.empty() ? 0 : std::accumulate(x.begin(), x.end(), 0.0) / x.size();
  const double ym = y.empty() ? 0 : std::accumulate(y.begin(), y.end(), 0.0) / y.size();
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k) sxy += (x[k] - xm) * (y[k] - ym), sxx += (x[k] - xm) * (x[k] - xm);
  if (x.size() >= 2 && sxx > 0) o.fit = sxy / sxx, o.fit_points = static_cast<int>(x.size());
  return o;
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
