// rpfem command line. The kernel never prints; this driver does.
#include <CLI/CLI.hpp>
#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <exception>

#include "app/calibrate_command.hpp"
#include "app/data_dir.hpp"
#include "app/run_command.hpp"
#include "app/slurm_task.hpp"
#include "app/subprocess.hpp"
#include "app/suite_command.hpp"
#include "app/sweep_command.hpp"
#include "app/verify_command.hpp"
#include "core/types.hpp"
#include "core/version.hpp"
#include "factory.hpp"

namespace {

// The sparse factorizations allocate their work arrays anew at every
// factorization (MUMPS under Ipopt most: Test II's die under ipopt took
// 127,752 page faults, glibc handing the arrays back to the system and the
// next factorization faulting them in again). Freed memory is kept in the
// heap up to 128 MB, and blocks below 32 MB come from it (glibc's own
// ceiling for its adaptive threshold): 6,948 faults, the same results
// (docs/decisions.md, "Linear algebra and the element loops").
void keep_freed_memory() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
}

constexpr const char* kForceHelp =
    "use a non-empty --out: what an earlier rpfem command wrote there is removed first (other files are kept); "
    "without it a non-empty --out is refused";

// `rpfem run`: one case.
CLI::App* add_run(CLI::App& app, rpfem::RunOptions& run) {
  std::string formulation_help =
      "contact enforcement, overriding the case's contact.enforcement (or ENFORCEMENT+DISCRETIZATION):";
  for (const auto& f : rpfem::formulations()) formulation_help += "\n  " + f.name + ": " + f.help;
  std::string discretization_help = "contact discretization, overriding the case's contact.discretization:";
  for (const auto& d : rpfem::discretizations()) discretization_help += "\n  " + d.name + ": " + d.help;
  auto* run_cmd = app.add_subcommand("run", "Run one case file; results in --out");
  run_cmd->add_option("case", run.case_file, "case file (TOML)")->required();
  run_cmd->add_option("--out,-o", run.out_dir, "output folder (created)")->required();
  run_cmd->add_option("--formulation,--enforcement,-f", run.formulation, formulation_help);
  run_cmd->add_option("--discretization,-d", run.discretization, discretization_help);
  run_cmd->add_option("--set,-s", run.overrides, "override a case value: key.path=value (repeatable)");
  run_cmd->add_option("--variant", run.variant,
                      "run a [[variants]] entry of the case (its overrides, then --set's); 'all': each into OUT/NAME");
  run_cmd->add_flag("--quiet,-q", run.quiet, "no progress output");
  run_cmd->add_flag("--force", run.force,
                    "use a non-empty --out: the run replaces its own files there (result.h5, result.xdmf, "
                    "history.csv, summary.json, events.csv; with --variant all the variant folders it no longer "
                    "runs), other files are kept; without it a non-empty --out is refused");
  return run_cmd;
}

// Where the runs of a command execute (app/run_engine.hpp).
void engine_options(CLI::App* cmd, rpfem::EngineOptions& e) {
  cmd->add_option("--engine", e.engine, "where the runs execute: local (this machine's cores) or slurm (job arrays; "
                                        "docs/cluster.md)")
      ->check(CLI::IsMember({"local", "slurm"}))
      ->capture_default_str();
  cmd->add_option("--partition", e.slurm.partition, "slurm: sbatch --partition");
  cmd->add_option("--time", e.slurm.time_limit, "slurm: each task's time limit (sbatch --time, e.g. 30:00)");
  cmd->add_option("--account", e.slurm.account, "slurm: sbatch --account");
  cmd->add_option("--mem", e.slurm.memory, "slurm: memory per task (sbatch --mem, e.g. 2G)");
  cmd->add_option("--sbatch-arg", e.slurm.extra, "slurm: one more sbatch argument (repeatable)");
  cmd->add_option("--array-limit", e.slurm.concurrency, "slurm: at most N tasks at once (the array's %N; 0: no limit)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option_function<std::string>(
         "--runs-per-task",
         [&e](const std::string& v) {
           if (v == "auto") {
             e.slurm.runs_per_task = 0;
             return;
           }
           char* end = nullptr;
           const long n = std::strtol(v.c_str(), &end, 10);
           if (end == v.c_str() || *end != '\0' || n < 1 || n > 1000000000)
             throw CLI::ValidationError("--runs-per-task", "expected a positive whole number or auto, got '" + v + "'");
           e.slurm.runs_per_task = static_cast<int>(n);
         },
         "slurm: each array task runs N runs one after another in one process (each in its own folder with its own "
         "exit code; --time is then the task's limit for all N); auto (the default): the cheapest run first as a "
         "task of its own, N from its time for tasks of about 5 minutes (docs/cluster.md)")
      ->type_name("N|auto");
}

// The options of the commands that run many cases on a worker pool.
template <class Options>
void pool_options(CLI::App* cmd, Options& o, const std::string& cases_help, const std::string& quick_help) {
  cmd->add_option("--cases", o.cases_dir, cases_help)->capture_default_str();
  cmd->add_option("--out,-o", o.out_dir, "output folder")->capture_default_str();
  cmd->add_option("--set,-s", o.overrides, "override a case value in every run: key.path=value");
  cmd->add_option("--jobs,-j", o.jobs, "runs in parallel (default: the machine's cores)");
  cmd->add_flag("--quick", o.quick, quick_help);
  cmd->add_flag("--quiet,-q", o.quiet, "no progress output");
  auto* force = cmd->add_flag("--force", o.force,
                              std::string(kForceHelp) + " (or --resume)");
  cmd->add_flag("--resume", o.engine.resume,
                "use a non-empty --out and keep its finished runs of the same request (case, formulation, variant, "
                "--set values); run the rest")
      ->excludes(force);
  engine_options(cmd, o.engine);
}

// `rpfem suite`: every scene and the studies, then the report.
CLI::App* add_suite(CLI::App& app, rpfem::SuiteOptions& suite) {
  suite.cases_dir = rpfem::data_dir() + "/cases";
  suite.out_dir = "out";
  suite.checks_file = rpfem::data_dir() + "/verification/checks.toml";
  auto* suite_cmd = app.add_subcommand(
      "suite", "Run every scene with every formulation that applies and the studies of CASES/studies, then the report");
  pool_options(suite_cmd, suite, "folder of case files (its studies/ folder: the studies)",
               "coarse meshes: half the divisions of every scene's mesh (run.mesh_factor = 0.5), the studies' "
               "reduced grids");
  suite_cmd->get_option("--set")->description(
      "override a case value in every scene run (not the studies'): key.path=value");
  suite_cmd->add_option("--scene", suite.scenes,
                        "run only these scenes (case file names without .toml), and the studies on them");
  suite_cmd->add_option("--formulation,-f", suite.formulations,
                        "run only these formulations in the scene runs (a study runs its own)");
  suite_cmd->add_option("--checks", suite.checks_file, "verification checks (TOML; empty: none)")->capture_default_str();
  suite_cmd->add_flag("!--no-variants", suite.variants, "skip the scenes' [[variants]]");
  auto* study_opt = suite_cmd->add_option(
      "--study", suite.studies,
      "run only these studies of CASES/studies (file names without .toml; default: all, or with --scene those on "
      "the scenes named)");
  suite_cmd->add_flag("!--no-studies", suite.run_studies, "skip the studies of CASES/studies")->excludes(study_opt);
  suite_cmd->add_flag("!--no-report", suite.report, "skip the report");
  return suite_cmd;
}

// `rpfem sweep`: one scene over a study's grid.
CLI::App* add_sweep(CLI::App& app, rpfem::SweepOptions& sweep, const std::string& cases_dir) {
  sweep.cases_dir = cases_dir;
  sweep.out_dir = "sweep_out";
  auto* sweep_cmd = app.add_subcommand("sweep", "Run one scene over a study's grid of numerical parameters; one table");
  sweep_cmd->add_option("study", sweep.study_file, "study file (TOML, e.g. cases/studies/*.toml)")->required();
  pool_options(sweep_cmd, sweep, "folder of the scenes a study names",
               "the study's reduced grid (its axes' quick values and quick_set)");
  return sweep_cmd;
}

// `rpfem verify`: the acceptance checks on a suite folder.
struct VerifyOptions {
  std::string dir, checks_file = rpfem::data_dir() + "/verification/checks.toml";
  bool quiet = false;
};
CLI::App* add_verify(CLI::App& app, VerifyOptions& v) {
  auto* verify_cmd = app.add_subcommand("verify", "Evaluate the acceptance checks on a suite folder");
  verify_cmd->add_option("dir", v.dir, "suite output folder")->required();
  verify_cmd->add_option("--checks", v.checks_file, "checks file (TOML)")->capture_default_str();
  verify_cmd->add_flag("--quiet,-q", v.quiet, "no table");
  return verify_cmd;
}

// `rpfem calibrate`: a case value from a target curve, or the smallest penalty.
CLI::App* add_calibrate(CLI::App& app, rpfem::CalibrateOptions& cal) {
  auto* cal_cmd = app.add_subcommand(
      "calibrate", "Identify a case value from a target curve, or (--auto-beta) the smallest penalty; NLopt, "
                   "one run per evaluation in OUT/evals (docs/calibrate.md)");
  cal_cmd->add_option("case", cal.case_file, "case file (TOML)")->required();
  cal_cmd->add_option("--out,-o", cal.out_dir, "output folder (created)")->required();
  cal_cmd->add_option("--formulation,-f", cal.formulation, "contact formulation of every run");
  cal_cmd->add_option("--set,-s", cal.overrides, "override a case value in every run: key.path=value");
  auto* target_opt = cal_cmd->add_option(
      "--target", cal.target,
      "target CSV: 'stroke_mm,load_kN' (load-stroke) or 'reduction_percent,inner_diameter_change_percent' (ring)");
  auto* param_opt = cal_cmd->add_option("--param", cal.param, "the case key to identify, e.g. dies.top_die.friction.m");
  cal_cmd->add_option("--load", cal.load_column,
                      "history column compared with a load-stroke target (default: the stepping reference's Fy)");
  cal_cmd->add_option("--monitor", cal.monitor, "history column compared with a ring target")->capture_default_str();
  cal_cmd->add_option("--height", cal.height,
                      "mm: the modelled height for a ring target's reduction = 100 stroke / height (default: the "
                      "initial mesh's height)");
  auto* beta_opt = cal_cmd->add_option("--auto-beta", cal.auto_beta,
                                       "find the smallest formulations.penalty.beta_factor with max "
                                       "max_penetration_rel <= TOL");
  beta_opt->excludes(target_opt)->excludes(param_opt);
  cal_cmd->add_option("--bounds", cal.bounds, "LO,HI of the value (--auto-beta: of beta_factor, default 1e-6,1e6)")
      ->delimiter(',')
      ->expected(2);
  cal_cmd->add_option("--x0", cal.x0, "starting value (default: the case's, else mid-bounds)");
  cal_cmd->add_option("--xtol", cal.xtol, "absolute tolerance on the value (default 1e-4; --auto-beta: on log10 "
                                          "beta_factor, default 0.01)");
  cal_cmd->add_option("--max-evals", cal.max_evals, "NLopt's evaluation limit")->capture_default_str();
  cal_cmd->add_flag("--quiet,-q", cal.quiet, "no progress output");
  cal_cmd->add_flag("--force", cal.force,
                    kForceHelp);
  engine_options(cal_cmd, cal.engine);
  return cal_cmd;
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  CLI::App app{"rpfem: rigid-plastic finite elements for metal forming with frictional contact"};
  app.set_version_flag("--version", rpfem::kVersion);
  app.require_subcommand(1);
  rpfem::RunOptions run;
  rpfem::SuiteOptions suite;
  rpfem::SweepOptions sweep;
  VerifyOptions verify;
  rpfem::CalibrateOptions cal;
  CLI::App* run_cmd = add_run(app, run);
  CLI::App* suite_cmd = add_suite(app, suite);
  CLI::App* sweep_cmd = add_sweep(app, sweep, suite.cases_dir);
  CLI::App* verify_cmd = add_verify(app, verify);
  CLI::App* cal_cmd = add_calibrate(app, cal);
  // A Slurm array task's runs (app/slurm_task.hpp): what the engine's task
  // script runs, no command of the user's (no group: not in --help).
  std::string task_runs;
  std::size_t task_first = 1, task_count = 1;
  CLI::App* task_cmd = app.add_subcommand("slurm-task", "one task of a Slurm job array (the engine's own)");
  task_cmd->group("");
  task_cmd->add_option("runs", task_runs)->required();
  task_cmd->add_option("first", task_first)->required();
  task_cmd->add_option("count", task_count)->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return rpfem::report_errors([&] {
    if (*run_cmd) return rpfem::run_command(run);
    if (*suite_cmd) return rpfem::suite_command(suite);
    if (*sweep_cmd) return rpfem::sweep_command(sweep);
    if (*cal_cmd) return rpfem::calibrate_command(cal);
    if (*task_cmd) return rpfem::slurm_task_command(task_runs, task_first, task_count);
    if (*verify_cmd) return rpfem::verify_command(verify.dir, verify.checks_file, verify.quiet);
    return 0;
  });
}
