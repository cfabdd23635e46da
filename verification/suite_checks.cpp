#include "suite_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/case_file.hpp"
#include "results.hpp"

namespace rpfem {

namespace {

const NamedValues<CheckMetric> kMetrics{{"load_difference", CheckMetric::LoadDifference},
                                        {"history_max", CheckMetric::HistoryMax},
                                        {"load_jump", CheckMetric::LoadJump},
                                        {"finished", CheckMetric::Finished}};

}  // namespace

const std::string& metric_name(CheckMetric metric) { return name_of(kMetrics, metric); }

std::vector<SuiteCheck> read_suite_checks(const std::string& path) {
  CaseFile file(path);
  std::vector<SuiteCheck> out;
  for (CaseSection s : file.root().table_array("check")) {
    SuiteCheck c;
    c.scene = s.text("scene", std::nullopt);
    c.formulation = s.text("formulation", std::nullopt);
    c.variant = s.text("variant", "");
    c.metric = s.choice("metric", std::nullopt, kMetrics);
    c.verifies = s.text("verifies", "");
    c.against = s.text("against", "");
    c.source = s.text("source", "");
    c.why = s.text("why", "");
    if (c.metric == CheckMetric::LoadDifference) {
      c.reference = s.text("reference", std::nullopt);
      c.column = s.text("load", std::nullopt);
      c.reference_scene = s.text("reference_scene", c.scene);
      c.reference_variant = s.text("reference_variant", "");
      c.reference_load = s.text("reference_load", c.column);
      c.from = s.real("from", 0.0, Range::nonnegative(), "mm of stroke");
      c.stroke_tolerance = s.real("stroke_tolerance", 0.0, Range::nonnegative(), "mm");
    }
    if (c.metric == CheckMetric::LoadJump) {
      c.column = s.text("load", std::nullopt);
      c.from = s.real("from", 0.0, Range::nonnegative(), "mm of stroke");
    }
    if (c.metric == CheckMetric::HistoryMax) {
      c.column = s.text("column", std::nullopt);
      c.floor = s.text("floor", "");
    }
    if (c.metric != CheckMetric::Finished) c.tolerance = s.real("tolerance", std::nullopt, Range::nonnegative(), "");
    out.push_back(c);
  }
  file.finish();
  return out;
}

namespace {

std::string run_dir(const std::string& suite, const std::string& scene, const std::string& f,
                    const std::string& variant = "") {
  return suite + "/" + scene + "/" + f + (variant.empty() ? "" : "/" + variant);
}

// The largest value (a non-finite one counts as infinite: it fails any check).
double largest(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::isfinite(x) ? x : INFINITY);
  return m;
}

}  // namespace

std::vector<CheckResult> evaluate_suite_checks(const std::string& suite_dir, const std::vector<SuiteCheck>& checks) {
  std::vector<CheckResult> out;
  for (const SuiteCheck& c : checks) {
    CheckResult r;
    r.check = c;
    const std::string dir = run_dir(suite_dir, c.scene, c.formulation, c.variant);
    try {
      if (!std::filesystem::exists(dir + "/history.csv")) throw std::runtime_error("no run in " + dir);
      if (c.metric == CheckMetric::Finished) {
        r.value = run_finished(dir) ? 1 : 0;
        r.pass = r.value == 1;
      } else if (c.metric == CheckMetric::HistoryMax) {
        const History h = read_history(dir + "/history.csv");
        const std::vector<double>& v = h.at(c.column);
        r.value = largest(v);
        r.pass = r.value <= c.tolerance;
        if (!c.floor.empty() && !r.pass) {
          // Each step against the larger of the tolerance and its floor.
          const std::vector<double>& f = h.at(c.floor);
          double worst = 0;
          for (std::size_t i = 0; i < v.size(); ++i) {
            const double allowed = std::max(c.tolerance, std::isfinite(f[i]) ? f[i] : 0.0);
            worst = std::max(worst, std::isfinite(v[i]) ? v[i] / allowed : INFINITY);
          }
          r.pass = worst <= 1;
          char buf[160];
          std::snprintf(buf, sizeof buf, "above the tolerance, within %s at every step (largest ratio %.2f)",
                        c.floor.c_str(), worst);
          r.note = r.pass ? buf : "";
        }
      } else if (c.metric == CheckMetric::LoadJump) {
        r.value = load_jump(read_history(dir + "/history.csv"), c.column, c.from);
        r.pass = r.value <= c.tolerance;
      } else {
        const History a = read_history(dir + "/history.csv");
        const History b =
            read_history(run_dir(suite_dir, c.reference_scene, c.reference, c.reference_variant) + "/history.csv");
        r.value = load_difference(a, c.column, b, c.reference_load, c.from, c.stroke_tolerance);
        r.pass = r.value <= c.tolerance;
      }
    } catch (const std::exception& e) {
      r.value = NAN;
      r.pass = false;
      r.note = e.what();
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace rpfem
