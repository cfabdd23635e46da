// `rpfem sweep STUDY.toml`: one scene over the grid of a study file
// (app/study.hpp), independent runs in parallel, then one table with a row
// per run (docs/sweeps.md):
//   OUT/runs/NNN/        each run's own folder (history.csv, summary.json)
//   OUT/reference/       the reference run, if the study names one
//   OUT/sweep.csv, OUT/sweep.h5   the table (io/table_writer.hpp)
//   OUT/sweep.json       the study, every override used, Richardson's
//                        estimates, the usable window, the reference run's
//                        own values, the errors' observed orders along a
//                        regularization axis, version, timings
// `rpfem suite` runs its studies through plan_sweep and write_sweep, their
// runs on the suite's own pool.
#pragma once
#include <chrono>
#include <string>
#include <vector>

#include "app/run_engine.hpp"
#include "app/study.hpp"
#include "material/flow_stress.hpp"

namespace rpfem {

struct SweepOptions {
  std::string study_file, out_dir, cases_dir;
  std::vector<std::string> overrides;  // --set, after the study's own
  int jobs = 0;                        // 0: the machine's cores
  bool quick = false;                  // the axes' quick values, quick_set
  bool quiet = false;
  bool force = false;  // --force: a non-empty out_dir is cleared of earlier outputs (else refused)
  EngineOptions engine;                // where the runs execute (local pool or Slurm)
};

// A study's runs before they run: the grid in row-major order (the last
// axis fastest), then the reference run if the study names one.
struct SweepPlan {
  SweepOptions options;
  Study study;
  std::vector<std::vector<std::size_t>> index;  // per grid run, its value's index on each axis
  std::vector<PoolRun> runs;                    // the grid's, then the reference
  std::string monitor_unit;                     // the study's monitor's (io/monitors.hpp: mm, percentage points, ...)
  FlowStressLaw exact_law;                      // reference kind "exact": the body's law
  EngineChoice engine;                          // how its runs ran (sweep.json "engine"), after they ran
  std::chrono::steady_clock::time_point start;
};

// Reads the study and every run's case with its overrides: bad input
// (InputError) comes before anything runs.
SweepPlan plan_sweep(const SweepOptions& opt);

// After the plan's runs ran (their rc and seconds filled): the table,
// sweep.h5 and sweep.json, and unless quiet the summary lines. Returns the
// number of grid runs that stopped early.
int write_sweep(const SweepPlan& plan);

// Exit code: 0 every run finished, 3 some stopped (the table says which),
// 2 bad input.
int sweep_command(const SweepOptions& opt);

}  // namespace rpfem
