// `rpfem run`: one scene, one formulation, results in one folder.
#pragma once
#include <string>
#include <vector>

namespace rpfem {

struct RunOptions {
  std::string case_file;
  std::string out_dir;
  std::string formulation;     // the enforcement, or ENFORCEMENT+DISCRETIZATION; empty: the scene's own
  std::string discretization;  // empty: the scene's own (or the formulation's)
  std::vector<std::string> overrides;
  std::string variant;  // empty: the base case; "all": every variant into out_dir/NAME
  bool quiet = false;
  bool force = false;  // --force: a non-empty out_dir is cleared of earlier outputs (else refused)
};

// Returns the process exit code: 0 finished, 2 bad input, 3 stopped early
// (finished steps saved, reason printed and in summary.json).
int run_command(const RunOptions& opt);

}  // namespace rpfem
