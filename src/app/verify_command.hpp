// `rpfem verify DIR`: the acceptance checks of verification/checks.toml (or
// --checks FILE) on a suite folder: prints the table (check, metric, value,
// tolerance, pass or fail), writes DIR/verification.json, exits 4 if any
// check fails (0 if all pass, 2 on bad input).
#pragma once
#include <string>
#include <vector>

namespace rpfem {

// only_scenes: evaluate only the checks whose scenes (and reference scenes)
// are among these (the suite's own verification); empty: every check.
int verify_command(const std::string& suite_dir, const std::string& checks_file, bool quiet,
                   const std::vector<std::string>& only_scenes = {});

}  // namespace rpfem
