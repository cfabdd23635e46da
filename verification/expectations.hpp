// A case's expected outcome, stated in the case file and checked on its
// runs (docs/case-format.md, [expect]):
//   [expect]                       the case's own run; [variants.expect]: a variant's
//   outcome = "finished"           or "stopped" (summary.json status)
//   reason_contains = ["..."]      stopped: words the stop reason must contain
//   warnings = ["..."]             each matches a recorded warning, and every
//                                  warning matches one (default: no warning)
//   [[expect.measure]]             a measured value and its bounds `min`, `max`:
//     what = "load_difference"     largest relative difference of |load| from a
//                                  reference run (verification/curve_comparison.hpp)
//     what = "history_max"         largest |value| of a history.csv column
//     what = "summary"             a number of summary.json
// A reference run is a case (`reference_case`, default this one, relative to
// this file) with overrides (`reference_set`) under a formulation
// (`reference_formulation`, default the case's own); a variant's reference
// does not take the variant's overrides.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "io/case_file.hpp"

namespace rpfem {

// One run the checks need: `rpfem run CASE [--variant V] [--formulation F]
// [--set O]...`, into RUNS_DIR/label.
struct ExpectedRun {
  std::string label, case_file, variant, formulation;
  std::vector<std::string> overrides;
  std::vector<std::string> arguments() const;  // after `rpfem run`, without --out
};

// [[expect.measure]] what, as above.
enum class MeasureKind { LoadDifference, HistoryMax, Summary };
// [expect] outcome: how the run must end (summary.json status).
enum class ExpectedEnd { Finished, Stopped };

// Their names in a case file ("load_difference", "finished", ...).
const std::string& measure_kind_name(MeasureKind what);
const std::string& outcome_name(ExpectedEnd outcome);

struct ExpectedMeasure {
  MeasureKind what = MeasureKind::Summary;
  std::string column;  // the load, history column or summary key
  std::string reference_load;
  int reference = -1;  // index into ExpectedCase::runs (load_difference)
  double from = 0, stroke_tolerance = 0;  // mm
  std::optional<double> min, max;
};

struct Expectation {
  int run = 0;  // index into ExpectedCase::runs
  ExpectedEnd outcome = ExpectedEnd::Finished;
  std::vector<std::string> reason_contains, warnings;
  std::vector<ExpectedMeasure> measures;
};

struct ExpectedCase {
  std::string file;
  std::vector<ExpectedRun> runs;  // the expectations' runs, then their references (no repeats)
  std::vector<Expectation> expectations;
};

// Validates the case's [expect] tables (its own and its variants');
// InputError naming the file and key on bad input. `root` is the case as
// `rpfem run` reads it: every [expect] key becomes known to finish().
void validate_expect_tables(CaseSection root, const std::string& case_file);
// The whole plan of one case file: its expectations and the runs they need.
ExpectedCase read_expected_case(const std::string& case_file);

struct MeasuredValue {
  std::string name;
  double value = 0;
  bool pass = false;
};

struct ExpectationResult {
  std::string run;  // label
  bool pass = false;
  std::string message;  // what failed, or "as expected"
  std::vector<MeasuredValue> values;
};

// Evaluates one expectation on the runs in runs_dir/<label>; every run it
// reads must have finite numbers only in history.csv and summary.json.
ExpectationResult evaluate_expectation(const ExpectedCase& c, const Expectation& e, const std::string& runs_dir);
// The first non-finite entry of a run's history.csv or summary.json (empty
// if none).
std::string non_finite_entries(const std::string& run_dir);

}  // namespace rpfem
