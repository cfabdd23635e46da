// Where the independent runs of `rpfem sweep` and `rpfem suite` execute:
// the local pool (app/run_pool.hpp) or a Slurm cluster, as job arrays
// (docs/cluster.md). Either way each run's results land in its folder and
// its exit code and wall time in its PoolRun, so the tables and reports
// that follow are the same.
//
// The Slurm engine writes WORK/slurm/commands.txt (line i: the exact `rpfem
// run` command of task i) and WORK/slurm/dirs.txt (its folder), submits one
// `sbatch --array` per MaxArraySize tasks, and polls `squeue` every second
// (not `sbatch --wait`, which polls every 32 s), printing the pool's lines
// (each ended run; every 10 s the counts and each running task's step,
// stroke and iterations from its history.csv).
// Before the arrays, a one-task `srun` writes a file into WORK/slurm from a
// compute node: a folder the nodes do not share is bad input, said so.
// Each array task runs its runs (--runs-per-task N, N of them) one after
// another in one process (app/slurm_task.hpp: a forked worker, as the local
// pool's), each in its own folder with its own exit code: one task's
// start-up and scheduling spread over N runs (docs/cluster.md has the
// measurements). Without N (or `auto`) the cheapest run goes first as a
// task of its own and its time chooses N (run_engine.cpp,
// choose_runs_per_task).
// Each task writes each run's exit code to DIR/exit_code; a task that ends
// without one (cancelled, out of time, its node lost, or a folder the node
// cannot write) is reported with its Slurm state and exit code, appended to
// DIR/run.log. Ctrl-C (or SIGTERM) cancels the arrays (scancel) and exits
// 130.
//
// With --resume (either engine), a run whose summary.json says finished
// and whose request (case file, formulation, discretization, variant and
// --set values: summary.json's "request") is this run's is not run again:
// the same command on the same folder resumes a study.
#pragma once
#include <string>
#include <vector>

#include "app/run_pool.hpp"

namespace rpfem {

struct SlurmOptions {
  std::string partition, time_limit, account, memory;  // sbatch -p, -t, -A, --mem (empty: the cluster's default)
  std::vector<std::string> extra;                      // more sbatch arguments, one word each
  int concurrency = 0;    // the array's %N: at most N tasks at once (0: no limit)
  int runs_per_task = 0;  // --runs-per-task: each array task runs this many runs one after another (0: auto)
  double poll_seconds = 1.0;
};

struct EngineOptions {
  std::string engine = "local";  // "local" or "slurm"
  SlurmOptions slurm;
  bool resume = false;  // --resume: a run whose folder holds the same request, finished, is not run again
};

// How the runs were run, for the study's record (sweep.json "engine").
struct EngineChoice {
  std::string engine = "local";
  int runs_per_task = 1;  // Slurm: runs per array task
  std::string rule;       // Slurm: "given" (--runs-per-task N), "auto", "auto: one run"
  double probe_run_s = 0, estimated_run_s = 0, task_target_s = 0;  // auto: the probe run's wall time, a run's
                                                                   // estimated time, the task's target
  int cpus = 0;  // auto: the partition's CPUs
};

// Runs `runs` (their rc and seconds filled). work_dir holds the engine's
// own files (Slurm: WORK/slurm/). jobs: the local pool's workers.
// Throws InputError for an unknown engine or a Slurm that cannot be used.
EngineChoice run_runs(std::vector<PoolRun>& runs, const std::string& work_dir, const EngineOptions& engine, int jobs,
                      bool quiet);

}  // namespace rpfem
