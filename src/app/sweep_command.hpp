// `rpfem sweep STUDY.toml`: one scene over the grid of a study file
// (app/study.hpp), independent runs in parallel, then one table with a row
// per run (docs/sweeps.md):
//   OUT/runs/NNN/        each run's own folder (history.csv, summary.json)
//   OUT/reference/       the reference run, if the study names one
//   OUT/sweep.csv, OUT/sweep.h5   the table (io/table_writer.hpp)
//   OUT/sweep.json       the study, every override used, Richardson's
//                        estimates, the usable window, version, timings
#pragma once
#include <string>
#include <vector>

namespace rpfem {

struct SweepOptions {
  std::string study_file, out_dir, cases_dir;
  std::vector<std::string> overrides;  // --set, after the study's own
  int jobs = 0;                        // 0: the machine's cores
  bool quick = false;                  // the axes' quick values, quick_set
  bool quiet = false;
};

// Exit code: 0 every run finished, 3 some stopped (the table says which),
// 2 bad input.
int sweep_command(const SweepOptions& opt);

}  // namespace rpfem
