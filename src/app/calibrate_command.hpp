// `rpfem calibrate`: identifies one case value from a measured curve, or
// (--auto-beta) the smallest penalty that keeps the penetration within a
// tolerance, with NLopt; every evaluation is one `rpfem run` into
// OUT/evals/NNN. Usage, formats and definitions: docs/calibrate.md.
//   OUT/calibration.json  setup, every evaluation, result, version, timing
//   OUT/evaluations.csv   evaluation,value,<misfit|max_penetration_rel>,wall_time_s,best
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/run_engine.hpp"

namespace rpfem {

struct CalibrateOptions {
  std::string case_file;
  std::string out_dir;
  std::string formulation;             // empty: the case's own (auto-beta: penalty)
  std::vector<std::string> overrides;  // --set, passed to every run
  // Fitting a curve:
  std::string target;                  // CSV (curve_fit.hpp)
  std::string param;                   // the case key identified
  std::string load_column;             // empty: <stepping reference>.Fy
  std::string monitor = "inner_diameter_mid";
  std::optional<double> height;        // mm, the modelled height (ring table); default: the mesh's
  // The penalty search:
  std::optional<double> auto_beta;     // tolerance on max_penetration_rel
  // Both:
  std::vector<double> bounds;          // LO,HI (auto-beta: of beta_factor, default 1e-6,1e6)
  std::optional<double> x0;
  std::optional<double> xtol;          // absolute on the value (auto-beta: on log10 beta_factor)
  int max_evals = 50;
  EngineOptions engine;                // where the evaluations run (local or Slurm)
  bool quiet = false;
  bool force = false;  // --force: a non-empty out_dir is cleared of earlier outputs (else refused)
};

// Exit code: 0 a result, 2 bad input, 3 a run failed (or no beta_factor in
// the bounds meets the tolerance); calibration.json records what was done.
int calibrate_command(const CalibrateOptions& opt);

}  // namespace rpfem
