#include "app/run_pool.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "app/linked_blas.hpp"
#include "app/run_command.hpp"
#include "app/run_worker.hpp"
#include "app/subprocess.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

using Clock = std::chrono::steady_clock;

// Where a run is, from the last row of its history.csv.
struct Progress {
  bool started = false;
  int step = 0, iterations = 0;
  double stroke = 0;
};

Progress read_progress(const std::string& dir) {
  std::ifstream in(dir + "/history.csv");
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string c; std::getline(ss, c, ',');) out.push_back(c);
    return out;
  };
  const auto names = split(header), values = split(last);
  Progress p;
  for (std::size_t c = 0; c < names.size() && c < values.size(); ++c) {
    char* end = nullptr;
    const double x = std::strtod(values[c].c_str(), &end);
    if (end == values[c].c_str()) continue;
    if (names[c] == "step") p.step = static_cast<int>(x), p.started = true;
    if (names[c] == "stroke") p.stroke = x;
    if (names[c] == "newton_iterations") p.iterations = static_cast<int>(x);
  }
  return p;
}

}  // namespace

void print_progress(const std::vector<PoolRun>& runs, const std::vector<RunClock>& slots, int workers,
                    double elapsed) {
  const auto now = Clock::now();
  double left = 0, longest = 0, finished_time = 0, projected = 0;
  int finished = 0, queued = 0, projections = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const PoolRun& j = runs[i];
    if (slots[i].ended) {
      finished_time += j.seconds, ++finished;
      continue;
    }
    if (!slots[i].running) {
      ++queued;
      continue;
    }
    const double run_s = std::chrono::duration<double>(now - slots[i].start).count();
    const Progress p = read_progress(j.dir);
    const double frac = j.end_stroke > 0 ? std::min(1.0, p.stroke / j.end_stroke) : 0.0;
    std::printf("  running %s: ", j.label.c_str());
    if (!p.started) {
      std::printf("starting, %.0f s\n", run_s);
      continue;
    }
    // Steps planned at the case's increment, or more where the run has cut
    // steps (landings, retries): the count so far over the stroke done.
    const int steps = frac > 0.02 ? std::max(j.steps, static_cast<int>(std::lround(p.step / frac))) : j.steps;
    std::printf("step %d of %s%d, stroke %.3f of %.3f mm, %d iterations, %.0f s", p.step,
                steps > j.steps ? "~" : "", steps, p.stroke, j.end_stroke, p.iterations, run_s);
    if (frac > 0.02) {
      const double rest = run_s * (1 - frac) / frac;
      left += rest, longest = std::max(longest, rest), projected += run_s + rest, ++projections;
      std::printf(", ~%.0f s left", rest);
    }
    std::printf("\n");
  }
  const double mean = finished ? finished_time / finished : (projections ? projected / projections : 0.0);
  if (mean > 0)
    std::printf("  all: %d of %zu runs done, %.0f s elapsed, ~%.0f s left\n", finished, runs.size(), elapsed,
                std::max(longest, (left + queued * mean) / std::max(1, workers)));
  std::fflush(stdout);
}

std::string run_command(const PoolRun& r, const std::string& self) {
  std::string cmd = shell_quote(self) + " run " + shell_quote(r.case_file) + " --out " + shell_quote(r.dir) + " --quiet --force";
  if (!r.formulation.empty()) cmd += " --formulation " + shell_quote(r.formulation);
  if (!r.variant.empty()) cmd += " --variant " + shell_quote(r.variant);
  for (const auto& o : r.overrides) cmd += " --set " + shell_quote(o);
  return cmd;
}

namespace {

// A run's folder, created here: a failure there (a full or read-only disk)
// is the run's, exit 2, not the pool thread's.
bool make_run_folder(PoolRun& r) {
  std::error_code ec;
  fs::create_directories(r.dir, ec);
  if (ec) r.rc = 2, r.seconds = 0;
  return !ec;
}

// A worker process for runs[i]: `rpfem run` with the options run_command(r,
// ...) writes, its log in the run's folder. The BLAS at one thread here
// first, so that a run at one BLAS thread (the default) finds it so and
// starts no thread server in the worker (linked_blas.hpp).
RunWorker run_worker(const std::vector<PoolRun>& runs) {
  set_blas_threads(1);
  return RunWorker([&runs](std::size_t i) { return runs[i].dir + "/run.log"; },
                   [&runs](std::size_t i) {
                     const PoolRun& r = runs[i];
                     RunOptions opt;
                     opt.case_file = r.case_file, opt.out_dir = r.dir, opt.formulation = r.formulation;
                     opt.variant = r.variant, opt.overrides = r.overrides;
                     opt.quiet = opt.force = true;
                     return run_command(opt);
                   });
}

// Runs runs[i] on the worker: fills its rc and seconds.
void run_on(RunWorker& worker, std::size_t i, PoolRun& result) {
  if (!make_run_folder(result)) return;
  const auto s0 = Clock::now();
  result.rc = worker.run(i);
  result.seconds = std::chrono::duration<double>(Clock::now() - s0).count();
}

}  // namespace

void run_one(PoolRun& r) {
  std::vector<PoolRun> one{r};
  run_in_turn(one, [](std::size_t) {});
  r.rc = one[0].rc, r.seconds = one[0].seconds;
}

void run_in_turn(std::vector<PoolRun>& runs, const std::function<void(std::size_t)>& ended) {
  RunWorker worker = run_worker(runs);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    run_on(worker, i, runs[i]);
    ended(i);
  }
}

void run_pool(std::vector<PoolRun>& runs, int jobs, bool quiet) {
  const int workers = std::max(1, jobs > 0 ? jobs : static_cast<int>(std::thread::hardware_concurrency()));
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex print;  // guards the slots, the runs' results and stdout
  std::vector<RunClock> slots(runs.size());
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  // Runs the caller marked finished before (rc 0: resumed) are not run.
  std::vector<char> kept(runs.size(), 0);
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (runs[i].rc == 0) kept[i] = 1, slots[i].ended = true, ++done;
  const int kept_count = done;
  std::vector<std::size_t> order(runs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return runs[a].cost > runs[b].cost; });
  auto work = [&] {
    RunWorker worker = run_worker(runs);  // started at its first run
    for (std::size_t n; (n = next++) < runs.size();) {
      const std::size_t i = order[n];
      if (kept[i]) continue;
      {
        std::lock_guard<std::mutex> lock(print);
        slots[i].start = Clock::now();
        slots[i].running = true;
      }
      PoolRun r = runs[i];  // run outside the lock; the results copied back under it
      run_on(worker, i, r);
      std::lock_guard<std::mutex> lock(print);
      PoolRun& j = runs[i];
      j.rc = r.rc, j.seconds = r.seconds;
      slots[i].ended = true;
      slots[i].running = false;
      const int k = ++done;
      if (!quiet) {
        std::printf("[%d/%zu] %s: %s in %.1f s (%.0f s elapsed)\n", k, runs.size(), j.label.c_str(),
                    j.rc == 0 ? "finished" : ("stopped, exit " + std::to_string(j.rc)).c_str(), j.seconds, elapsed());
        std::fflush(stdout);
      }
    }
  };
  if (!quiet) {
    std::printf("%zu runs on %d workers", runs.size(), workers);
    if (kept_count) std::printf(" (%d finished before, kept)", kept_count);
    std::printf("\n");
  }
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(work);
  // Progress of the runs in flight every 10 s.
  while (done < static_cast<int>(runs.size())) {
    for (int t = 0; t < 100 && done < static_cast<int>(runs.size()); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (quiet || done >= static_cast<int>(runs.size())) continue;
    std::lock_guard<std::mutex> lock(print);
    print_progress(runs, slots, workers, elapsed());
  }
  for (auto& t : pool) t.join();
}

}  // namespace rpfem
