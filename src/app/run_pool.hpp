// Independent runs on a pool of workers (`rpfem suite`, `rpfem sweep`),
// each `rpfem run` in a child process of its own (a fork of this one:
// app/subprocess.hpp, run_forked) into its own folder with its log in
// DIR/run.log; unless quiet, a line per finished run and, every
// 10 s, each running run's step, stroke and iterations (from its
// history.csv) and the pool's estimated time left.
#pragma once
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace rpfem {

struct PoolRun {
  std::string label;      // how progress lines name the run
  std::string case_name;  // the scene (the case file's name)
  std::string case_file, formulation, variant, dir;
  std::vector<std::string> overrides;  // --set, in order
  double end_stroke = 0;  // mm, for progress
  int steps = 0;          // steps planned at the case's stroke increment
  // What the run is expected to cost, relative to the pool's other runs
  // (estimated_cost): the pool starts the costliest first.
  double cost = 0;
  // Filled by run_pool:
  int rc = -1;            // the run's exit code (128 + N: ended by signal N; -1: no exit code)
  double seconds = 0;     // wall time
};

// Runs whose rc is 0 on entry (finished before, resumed) are not run. The
// others start in the order of their cost, the costliest first (longest
// processing time first: a long run started last would keep one worker
// busy alone at the end); runs of equal cost in their order.
void run_pool(std::vector<PoolRun>& runs, int jobs, bool quiet);

// A run's cost for the pool's order: its planned steps times its elements
// to the power 1.5 (a sparse factorization of a 2D mesh of n elements
// takes of the order of n^1.5 operations, Newton's iterations a step
// about the same at every size).
inline double estimated_cost(int planned_steps, long elements) {
  return planned_steps * std::pow(static_cast<double>(elements), 1.5);
}

// Where a run of a pool or an array is: queued, running since start, ended.
struct RunClock {
  bool running = false, ended = false;
  std::chrono::steady_clock::time_point start;
};

// One line per run in flight (step k of n, stroke, Newton or Ipopt
// iterations of the last step, elapsed and estimated remaining time from
// the stroke done, read from its history.csv), and the whole's estimate:
// the runs in flight's remaining time plus the queued runs at the mean
// time of the finished ones (or of the running ones' projections), over
// the workers, and no less than the longest run in flight.
void print_progress(const std::vector<PoolRun>& runs, const std::vector<RunClock>& clocks, int workers,
                    double elapsed);

// The exact `rpfem run` command line of a run (the executable `self`):
// what a Slurm task runs.
std::string run_command(const PoolRun& r, const std::string& self);

// One `rpfem run` into r.dir (created; its log in r.dir/run.log) in a
// child process forked from this one, the options run_command(r, ...)
// writes: fills r.rc and r.seconds. The pool's worker, and `rpfem
// calibrate`'s evaluations.
void run_one(PoolRun& r);

// The runs one after another in one forked worker process (app/run_worker.hpp;
// a new one after a run that crashed, which reports 128 + its signal), each as
// run_one runs it: their rc and seconds filled, ended(i) called in this
// process as run i ends. A bundled Slurm task's runs (app/slurm_task.hpp).
void run_in_turn(std::vector<PoolRun>& runs, const std::function<void(std::size_t)>& ended);

}  // namespace rpfem
