#include "app/calibration_runs.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/optimize_1d.hpp"
#include "app/output_folder.hpp"
#include "app/run_pool.hpp"
#include "core/version.hpp"
#include "io/result_writer.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

// The last non-empty line of a run's log: its error or stop reason.
std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

toml::array evaluations_json(const std::vector<Evaluation>& evals, const std::string& score_name) {
  toml::array a;
  for (const auto& e : evals) {
    toml::table t{{"evaluation", e.index}, {"value", e.value}, {"wall_time_s", e.wall_s}, {"dir", e.dir}};
    if (std::isfinite(e.score)) t.insert(score_name, e.score);  // never NaN in a result file
    a.push_back(std::move(t));
  }
  return a;
}

void write_evaluations_csv(const std::string& out_dir, const std::vector<Evaluation>& evals,
                           const std::string& score_name, double best_value) {
  std::ostringstream os;
  os.precision(10);
  os << "evaluation,value," << score_name << ",wall_time_s,best\n";
  for (const auto& e : evals)
    os << e.index << "," << exact_text(e.value) << "," << e.score << "," << e.wall_s << ","
       << (e.value == best_value ? 1 : 0) << "\n";
  write_text_atomically(out_dir + "/evaluations.csv", os.str());
}

}  // namespace

CachedRuns::CachedRuns(RunSpec spec, Score score)
    : spec_(std::move(spec)), score_(std::move(score)) {
  make_output_folder(spec_.out_dir);
  fs::remove_all(fs::path(spec_.out_dir) / "evals");
}

Evaluation CachedRuns::evaluate(double value, bool* cached) {
  ++requests_;
  if (auto it = by_value_.find(value); it != by_value_.end()) {
    if (cached) *cached = true;
    return done_[it->second];
  }
  if (cached) *cached = false;
  Evaluation e;
  e.index = static_cast<int>(done_.size()) + 1;
  e.value = value;
  char name[32];
  std::snprintf(name, sizeof name, "evals/%03d", e.index);
  e.dir = name;
  const std::string dir = (fs::path(spec_.out_dir) / e.dir).string();
  PoolRun run;
  run.case_file = spec_.case_file, run.formulation = spec_.formulation, run.dir = dir;
  run.overrides = spec_.overrides;
  run.overrides.push_back(spec_.key + "=" + exact_text(value));
  // One run at a time (each evaluation depends on the last): on this
  // machine directly, on Slurm as a one-task array.
  if (spec_.engine.engine == "local") {
    run_one(run);
  } else {
    std::vector<PoolRun> one{run};
    run_runs(one, spec_.out_dir, spec_.engine, 1, true);
    run = one[0];
  }
  e.wall_s = run.seconds;
  const int rc = run.rc;
  if (rc != 0)
    throw RunFailed("evaluation " + std::to_string(e.index) + " (" + spec_.key + " = " + exact_text(value) +
                    "): the run " + (rc == 3 ? "stopped early" : "failed") + " (exit " + std::to_string(rc) +
                    "): " + last_line(dir + "/run.log") + " [" + dir + "/run.log]");
  const std::string history = dir + "/history.csv";
  e.score = score_(read_history(history), history);
  if (!std::isfinite(e.score))
    throw RunFailed("evaluation " + std::to_string(e.index) + ": a non-finite result from " + history);
  done_.push_back(e);
  by_value_[value] = done_.size() - 1;
  return e;
}

CalibrationLog::CalibrationLog(const CalibrateOptions& opt, const SearchRecord& s, const CachedRuns& runs,
                               std::string score_name)
    : opt_(opt), runs_(runs), score_name_(std::move(score_name)), algorithm_(algorithm_code(s.algorithm)),
      t0_(std::chrono::steady_clock::now()) {
  toml::array user, own;
  for (const auto& o : opt.overrides) user.push_back(o);
  for (const auto& o : s.run_overrides) own.push_back(o);
  record_ = toml::table{{"mode", s.mode},
                     {"case", s.case_name},
                     {"case_file", fs::absolute(opt.case_file).string()},
                     {"formulation", s.formulation},
                     {"overrides", user},
                     {"run_overrides", own},
                     {"key", s.key},
                     {"bounds", toml::array{s.lo, s.hi}},
                     {"x0", s.x0},
                     {"xtol", s.xtol},
                     {"max_evals", opt.max_evals},
                     {"algorithm", algorithm_code(s.algorithm)},
                     {"algorithm_description", algorithm_description(s.algorithm)},
                     {"version", kVersion}};
}

double CalibrationLog::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
}

void CalibrationLog::write(const std::string& status, double best_value) {
  record_.insert_or_assign("status", status);
  record_.insert_or_assign("evaluations", evaluations_json(runs_.all(), score_name_));
  record_.insert_or_assign("simulations", static_cast<int64_t>(runs_.all().size()));
  record_.insert_or_assign("wall_time_s", seconds());
  std::ostringstream os;
  os << toml::json_formatter{record_} << "\n";
  write_text_atomically(opt_.out_dir + "/calibration.json", os.str());
  write_evaluations_csv(opt_.out_dir, runs_.all(), score_name_, best_value);
}

int CalibrationLog::stopped(const RunFailed& e) {
  record_.insert_or_assign("reason", e.what());
  write("stopped");
  std::fprintf(stderr, "rpfem calibrate: stopped: %s\n", e.what());
  return 3;
}

void CalibrationLog::print_end(int nlopt_result, const std::string& nlopt_result_name) const {
  if (opt_.quiet) return;
  const int sims = static_cast<int>(runs_.all().size());
  std::printf("simulations: %d (%d evaluations, %d from the cache); NLopt %s returned %s (%d)%s\n", sims,
              runs_.requests(), runs_.requests() - sims, algorithm_.c_str(), nlopt_result_name.c_str(), nlopt_result,
              nlopt_result == nlopt::MAXEVAL_REACHED ? ": not converged to --xtol, raise --max-evals" : "");
  std::printf("wall time %.1f s; %s/calibration.json\n", seconds(), opt_.out_dir.c_str());
}

std::optional<double> used_number(const CaseFile& file, const std::string& key) {
  return file.used().at_path(key).value<double>();
}

}  // namespace rpfem
