#include "app/run_engine.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "app/subprocess.hpp"
#include "core/types.hpp"
#include "results.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

using Clock = std::chrono::steady_clock;

// The wall time of the finished run of the same request r's folder holds,
// if it holds one. (A pool passes no --discretization: the request's is
// empty.)
std::optional<double> finished_before(const PoolRun& r) {
  const Summary s(r.dir);
  if (s.string("status").value_or("") != "finished") return std::nullopt;
  std::error_code ec;
  const fs::path want = fs::weakly_canonical(fs::absolute(r.case_file), ec);
  const fs::path had = fs::weakly_canonical(s.string("request.case_file").value_or(""), ec);
  const bool same = want == had && s.string("request.formulation").value_or("?") == r.formulation &&
                    s.string("request.discretization").value_or("?").empty() &&
                    s.string("request.variant").value_or("?") == r.variant && s.strings("request.set") == r.overrides;
  if (!same) return std::nullopt;
  return s.number("wall_time_s").value_or(0.0);
}

volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) { g_interrupted = 1; }

// The cluster's MaxArraySize (scontrol show config): an array's task ids
// run 0 to MaxArraySize - 1.
int max_array_size() {
  const std::string config = capture_shell("scontrol show config");
  const auto k = config.find("MaxArraySize");
  const int n = k == std::string::npos ? 0 : std::atoi(config.c_str() + config.find('=', k) + 1);
  return n > 1 ? n : 1001;
}

// The task's script: runs FIRST .. FIRST + PER - 1 (lines of commands.txt
// from OFFSET + id * PER + 1, as many as there are) one after another, each
// into the folder on the same line of dirs.txt, its exit code and wall time
// into that folder's exit_code as it ends (written beside it and renamed:
// the engine, polling, never reads it half written). A run that fails does not stop
// the task's later runs; the task exits with the first nonzero exit code.
std::string array_script(const std::string& slurm_dir, int runs_per_task) {
  const std::string q = shell_quote(slurm_dir);
  return "#!/bin/bash\n"
         "# One task of an rpfem job array (src/app/run_engine.cpp).\n"
         "per=" + std::to_string(runs_per_task) + "\n"
         "first=$((RPFEM_TASK_OFFSET + SLURM_ARRAY_TASK_ID * per + 1))\n"
         "total=$(wc -l < " + q + "/commands.txt)\n"
         "status=0\n"
         "for ((i = first; i < first + per && i <= total; ++i)); do\n"
         "  dir=$(sed -n \"${i}p\" " + q + "/dirs.txt)\n"
         "  cmd=$(sed -n \"${i}p\" " + q + "/commands.txt)\n"
         "  mkdir -p \"$dir\" || { [ $status -eq 0 ] && status=90; continue; }\n"
         "  t0=$(date +%s.%N)\n"
         "  bash -c \"$cmd\" > \"$dir/run.log\" 2>&1\n"
         "  rc=$?\n"
         "  t1=$(date +%s.%N)\n"
         "  echo \"$rc $(awk \"BEGIN { print $t1 - $t0 }\")\" > \"$dir/exit_code.tmp\"\n"
         "  mv -f \"$dir/exit_code.tmp\" \"$dir/exit_code\"\n"
         "  [ $status -eq 0 ] && status=$rc\n"
         "done\n"
         "exit $status\n";
}

struct Task {
  std::size_t run;  // index into runs
  std::string job;  // JOBID_TASK
  bool ended = false;
};

void run_slurm(std::vector<PoolRun>& runs, const std::string& work_dir, const SlurmOptions& o, bool quiet) {
  int rc = 0;
  capture_shell("sbatch --version", &rc);
  if (rc != 0)
    throw InputError("--engine slurm: sbatch is not on PATH (scripts/slurm-local start gives a test cluster; "
                     "docs/cluster.md)");
  const std::string self = self_executable();
  const std::string slurm_dir = fs::absolute(work_dir + "/slurm").string();
  fs::create_directories(slurm_dir);
  const auto t0 = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  // Kept from an earlier run of the same command (--resume): rc set.
  std::vector<std::size_t> todo;
  std::vector<RunClock> clocks(runs.size());
  const int per = std::max(1, o.runs_per_task);
  int done = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].rc == 0) {
      clocks[i].ended = true;
      ++done;
      continue;
    }
    todo.push_back(i);
  }
  {
    std::ofstream cmds(slurm_dir + "/commands.txt"), dirs(slurm_dir + "/dirs.txt"), sh(slurm_dir + "/array.sh");
    for (std::size_t i : todo) {
      PoolRun r = runs[i];
      r.dir = fs::absolute(r.dir).string();
      cmds << run_command(r, self) << "\n";
      dirs << r.dir << "\n";
      fs::remove(r.dir + "/exit_code");
      fs::remove(r.dir + "/exit_code.tmp");
      fs::remove(r.dir + "/run.log");  // a bundled run has started when its run.log appears
    }
    sh << array_script(slurm_dir, per);
    if (!cmds || !dirs || !sh) throw InputError("--engine slurm: cannot write to " + slurm_dir);
  }
  if (todo.empty()) {
    if (!quiet) std::printf("%zu runs on Slurm: 0 submitted, %d finished before (%s)\n", runs.size(), done, slurm_dir.c_str());
    return;
  }
  // The folder seen from a compute node: one short task writes a file
  // there, the same partition and account as the arrays (once per folder
  // and process: a calibration submits one run at a time).
  static std::set<std::string> shared;
  std::string where;
  if (!o.partition.empty()) where += " -p " + shell_quote(o.partition);
  if (!o.account.empty()) where += " -A " + shell_quote(o.account);
  if (!shared.count(slurm_dir + where)) {
    const std::string probe = slurm_dir + "/probe";
    fs::remove(probe);
    const std::string said = capture_shell("srun -N1 -n1 -t 1" + where + " touch " + shell_quote(probe), &rc);
    if (rc != 0 || !fs::exists(probe))
      throw InputError("--engine slurm: " + slurm_dir + " is not writable from a compute node (the output folder "
                       "must be on a filesystem the nodes share): " +
                       (said.empty() ? "a one-task srun ran but its file did not appear here" : said));
    fs::remove(probe);
    shared.insert(slurm_dir + where);
  }
  if (!quiet)
    std::printf("%zu runs on Slurm: %zu submitted, %d finished before (%s)\n", runs.size(), todo.size(), done,
                slurm_dir.c_str());
  // One array per MaxArraySize tasks, each task PER runs (the last one
  // fewer): run todo[k] is task k / PER of the whole.
  std::vector<Task> tasks;
  std::vector<std::string> jobs;
  const std::size_t task_count = (todo.size() + per - 1) / per;
  const std::size_t chunk = max_array_size();
  for (std::size_t first = 0; first < task_count; first += chunk) {
    const std::size_t n = std::min(chunk, task_count - first);
    std::string cmd = "sbatch --parsable -J rpfem --array=0-" + std::to_string(n - 1);
    if (o.concurrency > 0) cmd += "%" + std::to_string(o.concurrency);
    cmd += " -o " + shell_quote(slurm_dir + "/task-%A_%a.log");
    cmd += " --export=ALL,RPFEM_TASK_OFFSET=" + std::to_string(first * per);
    if (!o.partition.empty()) cmd += " -p " + shell_quote(o.partition);
    if (!o.time_limit.empty()) cmd += " -t " + shell_quote(o.time_limit);
    if (!o.account.empty()) cmd += " -A " + shell_quote(o.account);
    if (!o.memory.empty()) cmd += " --mem " + shell_quote(o.memory);
    for (const auto& a : o.extra) cmd.append(1, ' ').append(shell_quote(a));
    cmd.append(1, ' ').append(shell_quote(slurm_dir + "/array.sh"));
    std::string id = capture_shell(cmd, &rc);
    if (rc != 0) throw InputError("--engine slurm: sbatch refused the array: " + id);
    id = id.substr(0, id.find_first_of(";\n"));
    jobs.push_back(id);
    for (std::size_t k = first * per; k < std::min(todo.size(), (first + n) * per); ++k)
      tasks.push_back({todo[k], id + "_" + std::to_string(k / per - first)});
    if (!quiet)
      std::printf("  submitted job array %s: %zu tasks%s\n", id.c_str(), n,
                  per > 1 ? (" of up to " + std::to_string(per) + " runs").c_str() : "");
  }
  std::string job_list;
  for (const auto& j : jobs) job_list += (job_list.empty() ? "" : ",") + j;
  // Ctrl-C or a scheduler's SIGTERM cancels the arrays.
  g_interrupted = 0;
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = on_interrupt;
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  std::size_t ended = 0;
  auto last_report = Clock::now();
  while (ended < tasks.size()) {
    std::this_thread::sleep_for(std::chrono::duration<double>(o.poll_seconds));
    if (g_interrupted) {
      capture_shell("scancel " + shell_quote(job_list));
      std::fprintf(stderr, "rpfem: interrupted: cancelled Slurm job(s) %s; run the same command with --resume to resume\n",
                   job_list.c_str());
      std::exit(130);
    }
    // The tasks still queued or running, by JOBID_TASK.
    std::map<std::string, std::string> state;
    std::istringstream q(capture_shell("squeue -h -r -o '%i %t' -j " + shell_quote(job_list)));
    for (std::string id, st; q >> id >> st;) state[id] = st;
    int pending = 0, running = 0, failed = 0;
    for (Task& t : tasks) {
      if (t.ended) {
        failed += runs[t.run].rc != 0;
        continue;
      }
      PoolRun& r = runs[t.run];
      const auto it = state.find(t.job);
      const bool has_code = fs::exists(r.dir + "/exit_code");
      if (it != state.end() && !has_code) {
        // A bundled run waits in a running task until its run.log appears.
        const bool queued = it->second == "PD" || (per > 1 && !fs::exists(r.dir + "/run.log"));
        (queued ? pending : running)++;
        if (!queued && !clocks[t.run].running) clocks[t.run].running = true, clocks[t.run].start = Clock::now();
        continue;
      }
      t.ended = true, ++ended, ++done;
      clocks[t.run].ended = true, clocks[t.run].running = false;
      std::string how;
      if (has_code) {
        std::istringstream c(read_text(r.dir + "/exit_code"));
        c >> r.rc >> r.seconds;
        how = r.rc == 0 ? "finished" : "stopped, exit " + std::to_string(r.rc);
      } else {
        // Ended without its exit code: cancelled, out of time, failed to
        // start, or a folder this node cannot write.
        const std::string info = capture_shell("scontrol show job -o " + shell_quote(t.job));
        const auto field = [&](const std::string& k) {
          const auto a = info.find(k + "=");
          return a == std::string::npos ? std::string("unknown")
                                        : info.substr(a + k.size() + 1, info.find(' ', a) - a - k.size() - 1);
        };
        r.rc = -1;
        how = "Slurm " + field("JobState") + ", exit code " + field("ExitCode");
        std::ofstream(r.dir + "/run.log", std::ios::app)
            << "rpfem: Slurm task " << t.job << " ended " << field("JobState") << " (exit code " << field("ExitCode")
            << ", reason " << field("Reason") << ") without its exit code in " << r.dir
            << " (the output folder must be on a filesystem the nodes share)\n";
      }
      failed += r.rc != 0;
      if (!quiet)
        std::printf("[%d/%zu] %s: %s in %.1f s (%.0f s elapsed)\n", done, runs.size(), r.label.c_str(), how.c_str(),
                    r.seconds, elapsed());
    }
    if (!quiet && std::chrono::duration<double>(Clock::now() - last_report).count() >= 10) {
      std::printf("  slurm %s: %d pending, %d running, %zu done, %d failed, %.0f s elapsed\n", job_list.c_str(), pending,
                  running, ended, failed, elapsed());
      print_progress(runs, clocks, std::max(1, running), elapsed());
      last_report = Clock::now();
    }
    std::fflush(stdout);
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
}

}  // namespace

void run_runs(std::vector<PoolRun>& runs, const std::string& work_dir, const EngineOptions& engine, int jobs,
              bool quiet) {
  for (auto& r : runs) r.rc = -1;
  if (engine.resume)
    for (auto& r : runs)
      if (const auto seconds = finished_before(r)) r.rc = 0, r.seconds = *seconds;
  if (engine.engine == "local")
    run_pool(runs, jobs, quiet);
  else if (engine.engine == "slurm")
    run_slurm(runs, work_dir, engine.slurm, quiet);
  else
    throw InputError("--engine: '" + engine.engine + "' is unknown; expected local or slurm");
}

}  // namespace rpfem
