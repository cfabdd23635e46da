// The simulations of `rpfem calibrate`: one `rpfem run` subprocess per value
// of the searched case key, into OUT/evals/NNN (history.csv, summary.json,
// result files and run.log kept), cached by value; and the records every
// calibration writes (OUT/calibration.json, OUT/evaluations.csv).
#pragma once
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlopt.hpp>
#include <toml++/toml.h>

#include "app/calibrate_command.hpp"
#include "app/run_engine.hpp"
#include "io/case_file.hpp"
#include "results.hpp"

namespace rpfem {

struct RunSpec {
  std::string case_file;
  std::string formulation;             // empty: the case's own
  std::vector<std::string> overrides;  // --set before the key's: the user's, then the calibration's own
  std::string key;                     // the case key searched
  std::string out_dir;                 // the calibration's folder
  EngineOptions engine;                // where each run executes (its Slurm files: OUT/slurm)
};

struct Evaluation {
  int index = 0;       // 1, 2, ... in the order run
  double value = 0;    // of the key
  double score = 0;    // the misfit or penetration computed from the run
  double wall_s = 0;   // the run's wall time (the subprocess)
  std::string dir;     // evals/NNN, relative to the calibration's folder
};

// A run that did not finish (non-zero exit): the calibration stops.
struct RunFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CachedRuns {
 public:
  // score: from the run's history.csv (its folder given for messages).
  using Score = std::function<double(const History&, const std::string& history_path)>;
  // Creates OUT (InputError where it cannot be) and clears OUT/evals (the
  // folders of an earlier calibration into OUT).
  CachedRuns(RunSpec spec, Score score);
  // The cached evaluation of this exact value, else a new run. Throws
  // RunFailed if the run exits non-zero.
  Evaluation evaluate(double value, bool* cached = nullptr);
  const std::vector<Evaluation>& all() const { return done_; }
  int requests() const { return requests_; }  // evaluate() calls, cached ones included

 private:
  RunSpec spec_;
  Score score_;
  std::vector<Evaluation> done_;
  std::map<double, std::size_t> by_value_;
  int requests_ = 0;
};

// What a search is: recorded at the top of calibration.json.
struct SearchRecord {
  std::string mode;                        // "fit" or "auto_beta"
  std::string case_name, formulation;      // the scene's name, the formulation run
  std::vector<std::string> run_overrides;  // the calibration's own --set (after the user's)
  std::string key;
  double lo = 0, hi = 0, x0 = 0, xtol = 0;
  nlopt::algorithm algorithm = nlopt::LN_BOBYQA;
};

// OUT/calibration.json: the search (SearchRecord), what the mode adds
// (record()), then on write() the status, every evaluation (the score
// under score_name), the number of simulations and the wall time since
// construction; and OUT/evaluations.csv.
class CalibrationLog {
 public:
  CalibrationLog(const CalibrateOptions& opt, const SearchRecord& s, const CachedRuns& runs, std::string score_name);
  toml::table& record() { return record_; }
  // best_value: the result's value (NaN: none), marked in evaluations.csv.
  void write(const std::string& status, double best_value = NAN);
  // A failed run: recorded (status "stopped", its reason) and printed; 3.
  int stopped(const RunFailed& e);
  // The closing lines: simulations, evaluations, NLopt's return, wall time.
  void print_end(int nlopt_result, const std::string& nlopt_result_name) const;
  double seconds() const;

 private:
  const CalibrateOptions& opt_;
  const CachedRuns& runs_;
  std::string score_name_, algorithm_;
  toml::table record_;
  std::chrono::steady_clock::time_point t0_;
};

// The number the case uses at key (after its overrides), if it uses one.
std::optional<double> used_number(const CaseFile& file, const std::string& key);

}  // namespace rpfem
