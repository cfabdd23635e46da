#include "suite_checks.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "curve_comparison.hpp"
#include "io/case_file.hpp"
#include "results.hpp"

namespace rpfem {

std::vector<SuiteCheck> read_suite_checks(const std::string& path) {
  CaseFile file(path);
  std::vector<SuiteCheck> out;
  for (CaseSection s : file.root().table_array("check")) {
    SuiteCheck c;
    c.scene = s.text("scene", std::nullopt);
    c.formulation = s.text("formulation", std::nullopt);
    c.variant = s.text("variant", "");
    c.metric = s.text("metric", std::nullopt, {"load_difference", "history_max", "finished"});
    c.issue = s.text("issue", "");
    if (c.metric == "load_difference") {
      c.reference = s.text("reference", std::nullopt);
      c.column = s.text("load", std::nullopt);
      c.reference_scene = s.text("reference_scene", c.scene);
      c.reference_load = s.text("reference_load", c.column);
      c.from = s.real("from", 0.0, Range::nonnegative(), "mm of stroke");
      c.stroke_tolerance = s.real("stroke_tolerance", 0.0, Range::nonnegative(), "mm");
    }
    if (c.metric == "history_max") c.column = s.text("column", std::nullopt);
    if (c.metric != "finished") c.tolerance = s.real("tolerance", std::nullopt, Range::nonnegative(), "");
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

bool finished(const std::string& dir) {
  std::ifstream in(dir + "/summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string s = ss.str();
  const auto k = s.find("\"status\"");
  if (k == std::string::npos) return false;
  const auto q1 = s.find('"', s.find(':', k)), q2 = s.find('"', q1 + 1);
  return q1 != std::string::npos && q2 != std::string::npos && s.substr(q1 + 1, q2 - q1 - 1) == "finished";
}

// The largest value (a non-finite one counts as infinite: it fails any check).
double largest(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::isfinite(x) ? x : INFINITY);
  return m;
}

std::vector<double> magnitudes(const std::vector<double>& v) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [](double x) { return std::abs(x); });
  return out;
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
      if (c.metric == "finished") {
        r.value = finished(dir) ? 1 : 0;
        r.pass = r.value == 1;
      } else if (c.metric == "history_max") {
        r.value = largest(read_history(dir + "/history.csv").at(c.column));
        r.pass = r.value <= c.tolerance;
      } else {
        const History a = read_history(dir + "/history.csv");
        const History b = read_history(run_dir(suite_dir, c.reference_scene, c.reference) + "/history.csv");
        r.value = curve_difference(a.at("stroke"), magnitudes(a.at(c.column)), b.at("stroke"),
                                   magnitudes(b.at(c.reference_load)), c.from, c.stroke_tolerance)
                      .worst;
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
