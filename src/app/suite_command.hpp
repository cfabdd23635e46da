// `rpfem suite`: every scene of a cases folder with every formulation that
// treats its contacts (a scene with rigid dies only: each formulation that
// treats dies; with contact between bodies: each that treats bodies; with
// no contact: its own), the scene's [[variants]] with its own formulation,
// and the studies of CASES/studies (app/suite_studies.hpp), independent
// runs in parallel on one pool; then the comparison report.
//   OUT/<case>/<formulation>/           base runs
//   OUT/<case>/<formulation>/<variant>/ variants (the scene's formulation)
//   OUT/studies/<study>/                a study's runs and tables, as `rpfem
//                                       sweep` writes them (sweep.csv, .h5, .json)
//   OUT/suite.json                      the program (executable, version,
//                                       compiler); the runs: case, formulation,
//                                       variant, folder, exit code, wall time;
//                                       the studies: folder, tables, runs stopped
//   OUT/verification.json               the checks of the scenes that ran
//                                       (`rpfem verify`; a failed check is
//                                       reported, it does not stop the suite)
//   OUT/report.html, OUT/report.md      reports/make_report.py (figures in
//                                       OUT/report_files/)
#pragma once
#include <string>
#include <vector>

#include "app/run_engine.hpp"

namespace rpfem {

struct SuiteOptions {
  std::string cases_dir;
  std::string out_dir;
  std::vector<std::string> scenes;        // empty: all
  std::vector<std::string> formulations;  // empty: all that apply
  std::vector<std::string> overrides;     // --set, passed to every run
  int jobs = 0;                           // 0: the machine's cores
  std::string checks_file;  // verification checks (empty: none)
  bool quick = false;  // run.mesh_factor = 0.5 in every run
  std::vector<std::string> studies;       // --study: only these (empty: by --scene)
  bool run_studies = true;                // false: --no-studies
  bool variants = true;
  bool report = true;
  bool quiet = false;
  bool force = false;  // --force: a non-empty out_dir is cleared of earlier outputs (else refused)
  EngineOptions engine;  // where the runs execute (local pool or Slurm)
};

// Exit code: 0 all runs finished and the report was built, 3 a scene's run
// or a study's reference run stopped early, or the report failed (the rest
// still ran), 2 bad input. A study's grid run that stops is an outcome its
// table records (finished 0, the reason), as `rpfem sweep` writes it; it
// does not change the exit code.
int suite_command(const SuiteOptions& opt);

}  // namespace rpfem
