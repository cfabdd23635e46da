// The contact formulations' acceptance checks as data (verification/
// checks.toml), evaluated on a suite folder written by `rpfem suite`
// (runs in DIR/<scene>/<formulation>[/<variant>]/):
//   metric = "load_difference": the largest relative difference of the
//            run's |load| from the `reference` formulation's run of
//            `reference_scene` (default: the same scene; its variant
//            `reference_variant`, default none), column
//            `reference_load` (default: `load`)
//            (verification/curve_comparison.hpp; from `from` mm of stroke,
//            within `stroke_tolerance` mm), at most `tolerance`;
//   metric = "history_max": the largest value of a history.csv column over
//            the run's steps, at most `tolerance`; with `floor` (a column
//            of the evaluation's own round-off, e.g. kkt_round_off), each
//            step at most the larger of `tolerance` and its floor value
//            (the note then says the tolerance itself was out of reach);
//   metric = "load_jump": the largest step-to-step change of the run's |load|
//            beyond the trend of its neighbouring steps, relative to the
//            load (verification/curve_comparison.hpp, curve_jump; from
//            `from` mm of stroke), at most `tolerance`;
//   metric = "finished": the run finished (summary.json status).
// Each check may say what it verifies (`verifies`), the kind of reference
// it is held against (`against`: an exact solution, another formulation,
// the Kuhn-Tucker conditions...), where that reference or its tolerance
// comes from (`source`) and why the tolerance is what it is (`why`); the
// shipped checks say all four (docs/verification.md lists them).
#pragma once
#include <string>
#include <vector>

namespace rpfem {

// A check's metric, as above.
enum class CheckMetric { LoadDifference, HistoryMax, LoadJump, Finished };
// Its name in checks.toml ("load_difference", ...).
const std::string& metric_name(CheckMetric metric);

struct SuiteCheck {
  std::string scene, formulation, variant;
  CheckMetric metric = CheckMetric::Finished;
  std::string reference, reference_scene, reference_variant, reference_load, column, floor;
  std::string verifies, against, source, why;  // documentation, as above
  double tolerance = 0, from = 0, stroke_tolerance = 0;
};

struct CheckResult {
  SuiteCheck check;
  double value = 0;
  bool pass = false;
  std::string note;  // why it could not be evaluated, if so
};

// Reads [[check]] tables; InputError naming the file and key on bad input.
std::vector<SuiteCheck> read_suite_checks(const std::string& path);
// Evaluates every check on the suite folder; a missing run fails its check.
std::vector<CheckResult> evaluate_suite_checks(const std::string& suite_dir, const std::vector<SuiteCheck>& checks);

}  // namespace rpfem
