// The studies `rpfem suite` runs besides its scenes: the study files of
// CASES/studies (docs/sweeps.md), each into OUT/studies/NAME as `rpfem
// sweep` would write it, their runs on the suite's pool.
#pragma once
#include <string>
#include <vector>

#include "app/suite_command.hpp"
#include "app/sweep_command.hpp"

namespace rpfem {

// The studies selected, planned (bad input throws before anything runs):
// with --study NAME those named (file names without .toml); else, with
// --scene, the studies on the scenes named; else all; none with
// --no-studies. The suite's --formulation and --set do not reach a study
// (its grid is its own), its --quick gives the studies' reduced grids.
// Unless quiet, one line names the studies left out and why.
std::vector<SweepPlan> plan_studies(const SuiteOptions& opt);

}  // namespace rpfem
