#include "app/verify_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <toml++/toml.h>

#include "io/result_writer.hpp"
#include "suite_checks.hpp"

namespace rpfem {

int verify_command(const std::string& suite_dir, const std::string& checks_file, bool quiet,
                   const std::vector<std::string>& only_scenes) {
  // A folder `rpfem suite` wrote holds suite.json; anything else is bad
  // input (each check would otherwise fail as "no run").
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(suite_dir, ec))
    throw InputError("verify: '" + suite_dir + "': no such folder; expected the --out folder of `rpfem suite`");
  if (!fs::is_regular_file(fs::path(suite_dir) / "suite.json", ec))
    throw InputError("verify: '" + suite_dir + "' is not a suite's folder (no suite.json); expected the --out " +
                     "folder of `rpfem suite`");
  std::vector<SuiteCheck> checks = read_suite_checks(checks_file);
  if (!only_scenes.empty()) {
    const auto ran = [&](const std::string& s) {
      return s.empty() || std::find(only_scenes.begin(), only_scenes.end(), s) != only_scenes.end();
    };
    checks.erase(std::remove_if(checks.begin(), checks.end(),
                                [&](const SuiteCheck& c) { return !ran(c.scene) || !ran(c.reference_scene); }),
                 checks.end());
  }
  const std::vector<CheckResult> results = evaluate_suite_checks(suite_dir, checks);
  toml::array rows;
  int failed = 0;
  if (!quiet)
    std::printf("%-36s %-8s %-34s %10s %10s  %s\n", "scene", "formul.", "metric", "value", "tolerance", "result");
  for (const auto& r : results) {
    const SuiteCheck& c = r.check;
    std::string metric = metric_name(c.metric);
    if (c.metric == CheckMetric::LoadDifference)
      metric += " vs " + (c.reference_scene == c.scene ? "" : c.reference_scene + " ") + c.reference +
                (c.reference_variant.empty() ? "" : " " + c.reference_variant) + " (" + c.column + ")";
    if (c.metric == CheckMetric::HistoryMax || c.metric == CheckMetric::LoadJump) metric += " " + c.column;
    failed += r.pass ? 0 : 1;
    if (!quiet)
      std::printf("%-36s %-8s %-34s %10.3e %10.3e  %s%s%s\n", c.scene.c_str(),
                  (c.formulation + (c.variant.empty() ? "" : " " + c.variant)).c_str(), metric.c_str(), r.value,
                  c.tolerance, r.pass ? "pass" : "FAIL", r.note.empty() ? "" : ": ", r.note.c_str());
    toml::table t{{"scene", c.scene}, {"formulation", c.formulation}, {"variant", c.variant}, {"metric", metric},
                  {"tolerance", c.tolerance}, {"pass", r.pass}, {"verifies", c.verifies}, {"against", c.against}};
    if (std::isfinite(r.value)) t.insert("value", r.value);  // never NaN in a result file
    if (!r.note.empty()) t.insert("note", r.note);
    rows.push_back(std::move(t));
  }
  std::ostringstream os;
  os << toml::json_formatter{toml::table{{"checks", rows}, {"failed", failed}}} << "\n";
  write_text_atomically(suite_dir + "/verification.json", os.str());
  if (!quiet) std::printf("%zu checks, %d failed; %s/verification.json\n", results.size(), failed, suite_dir.c_str());
  return failed ? 4 : 0;
}

}  // namespace rpfem
