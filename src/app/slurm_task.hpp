// One task of a Slurm job array (app/run_engine.hpp): its runs, read from
// the engine's WORK/slurm/runs.txt, one after another in one forked worker
// process as the local pool runs them (app/run_pool.hpp, run_in_turn), each
// into its own folder with its own run.log, and its exit code and wall time
// written to DIR/exit_code as it ends (beside it and renamed: the engine,
// polling, never reads it half written).
//
// Why not a process per run (docs/decisions.md, "Bundled Slurm tasks"):
// a one-step run's `rpfem run` process took 0.43 to 0.56 s of wall time
// in a bundled task, the run itself 0.11 to 0.17 s of it.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "app/run_pool.hpp"

namespace rpfem {

// WORK/slurm/runs.txt: line i is run i's folder, case file, formulation,
// variant and --set values, tab-separated (a tab, newline or backslash
// inside a field escaped as \t, \n, \\).
void write_task_runs(const std::string& path, const std::vector<PoolRun>& runs);
std::vector<PoolRun> read_task_runs(const std::string& path, std::size_t first, std::size_t count);

// `rpfem slurm-task RUNS FIRST COUNT` (what a task's script runs; no user
// command): lines FIRST to FIRST + COUNT - 1 of RUNS (from 1; as many as
// there are). A run that fails does not stop the later runs. Returns the
// first nonzero exit code of its runs (0: all finished); 90 where a run's
// exit code cannot be written into its folder.
int slurm_task_command(const std::string& runs_file, std::size_t first, std::size_t count);

}  // namespace rpfem
