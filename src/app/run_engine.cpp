#include "app/run_engine.hpp"

#include <algorithm>
#include <cmath>
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

#include "app/slurm_task.hpp"
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

// The task's script: lines OFFSET + id * PER + 1 to OFFSET + (id + 1) * PER
// of runs.txt (as many as there are) in one process (app/slurm_task.hpp);
// OFFSET and PER come with each array (sbatch --export).
std::string array_script(const std::string& self, const std::string& slurm_dir) {
  return "#!/bin/bash\n"
         "# One task of an rpfem job array (src/app/run_engine.cpp): its runs in one process.\n"
         "exec " + shell_quote(self) + " slurm-task " + shell_quote(slurm_dir + "/runs.txt") +
         " $((RPFEM_TASK_OFFSET + SLURM_ARRAY_TASK_ID * RPFEM_RUNS_PER_TASK + 1)) \"$RPFEM_RUNS_PER_TASK\"\n";
}

// Slurm's time format ([D-]HH:MM:SS, [D-]HH:MM, MM:SS, MM): seconds, 0 if
// not one of them.
double slurm_seconds(const std::string& t) {
  long days = 0, v[3] = {0, 0, 0};
  std::string rest = t;
  if (const auto d = t.find('-'); d != std::string::npos) days = std::atol(t.c_str()), rest = t.substr(d + 1);
  int n = 0;
  for (std::size_t a = 0; n < 3; ++n) {
    v[n] = std::atol(rest.c_str() + a);
    a = rest.find(':', a);
    if (a == std::string::npos) break;
    ++a;
  }
  const bool with_days = t.find('-') != std::string::npos;
  // MM, MM:SS, HH:MM:SS; with days: D-HH, D-HH:MM, D-HH:MM:SS.
  double s = n == 0 ? (with_days ? v[0] * 3600.0 : v[0] * 60.0)
             : n == 1 ? (with_days ? v[0] * 3600.0 + v[1] * 60.0 : v[0] * 60.0 + v[1])
                      : v[0] * 3600.0 + v[1] * 60.0 + v[2];
  return days * 86400.0 + s;
}

// The CPUs of the partition (or of the whole cluster): sinfo's %C is
// allocated/idle/other/total.
int cluster_cpus(const std::string& partition) {
  const std::string out =
      capture_shell("sinfo -h -o %C" + (partition.empty() ? std::string() : " -p " + shell_quote(partition)));
  int total = 0;
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);) {
    const auto k = line.rfind('/');
    if (k != std::string::npos) total += std::atoi(line.c_str() + k + 1);
  }
  return std::max(1, total);
}

struct Task {
  std::size_t run;  // index into runs
  std::string job;  // JOBID_TASK
  bool bundled = false;  // the task runs more than one run: a run waits until its run.log appears
  bool ended = false;
};

// A study's runs as job arrays: submitted a part at a time (submit), then
// waited for (wait), the progress lines the pool's.
class SlurmArrays {
 public:
  SlurmArrays(std::vector<PoolRun>& runs, const SlurmOptions& o, bool quiet, std::string slurm_dir, int done)
      : runs_(runs), o_(o), quiet_(quiet), slurm_dir_(std::move(slurm_dir)), clocks_(runs.size()), done_(done) {
    for (std::size_t i = 0; i < runs.size(); ++i) clocks_[i].ended = runs[i].rc == 0;
  }

  // Lines from + 1 to to of runs.txt (todo[from] to todo[to - 1]) as tasks of
  // per runs, in arrays of MaxArraySize tasks.
  void submit(const std::vector<std::size_t>& todo, std::size_t from, std::size_t to, int per) {
    const std::size_t task_count = (to - from + per - 1) / per;
    const std::size_t chunk = max_array_size();
    int rc = 0;
    for (std::size_t first = 0; first < task_count; first += chunk) {
      const std::size_t n = std::min(chunk, task_count - first);
      std::string cmd = "sbatch --parsable -J rpfem --array=0-" + std::to_string(n - 1);
      if (o_.concurrency > 0) cmd += "%" + std::to_string(o_.concurrency);
      cmd += " -o " + shell_quote(slurm_dir_ + "/task-%A_%a.log");
      cmd += " --export=ALL,RPFEM_TASK_OFFSET=" + std::to_string(from + first * per) +
             ",RPFEM_RUNS_PER_TASK=" + std::to_string(per);
      if (!o_.partition.empty()) cmd += " -p " + shell_quote(o_.partition);
      if (!o_.time_limit.empty()) cmd += " -t " + shell_quote(o_.time_limit);
      if (!o_.account.empty()) cmd += " -A " + shell_quote(o_.account);
      if (!o_.memory.empty()) cmd += " --mem " + shell_quote(o_.memory);
      for (const auto& a : o_.extra) cmd.append(1, ' ').append(shell_quote(a));
      cmd.append(1, ' ').append(shell_quote(slurm_dir_ + "/array.sh"));
      std::string id = capture_shell(cmd, &rc);
      if (rc != 0) throw InputError("--engine slurm: sbatch refused the array: " + id);
      id = id.substr(0, id.find_first_of(";\n"));
      jobs_.push_back(id);
      for (std::size_t k = from + first * per; k < std::min(to, from + (first + n) * per); ++k)
        tasks_.push_back({todo[k], id + "_" + std::to_string((k - from) / per - first), per > 1});
      if (!quiet_)
        std::printf("  submitted job array %s: %zu tasks%s\n", id.c_str(), n,
                    per > 1 ? (" of up to " + std::to_string(per) + " runs").c_str() : "");
    }
  }

  // Until every task submitted has ended. Ctrl-C or a scheduler's SIGTERM
  // cancels the arrays.
  void wait() {
    std::string job_list;
    for (const auto& j : jobs_) job_list += (job_list.empty() ? "" : ",") + j;
    g_interrupted = 0;
    struct sigaction sa {}, old_int {}, old_term {};
    sa.sa_handler = on_interrupt;
    sa.sa_flags = SA_RESTART;  // a poll's read of squeue is not cut short by the signal
    sigaction(SIGINT, &sa, &old_int);
    sigaction(SIGTERM, &sa, &old_term);
    std::size_t ended = 0;
    for (const Task& t : tasks_) ended += t.ended;
    auto last_report = Clock::now();
    while (ended < tasks_.size()) {
      std::this_thread::sleep_for(std::chrono::duration<double>(o_.poll_seconds));
      if (g_interrupted) {
        capture_shell("scancel " + shell_quote(job_list));
        std::fprintf(stderr,
                     "rpfem: interrupted: cancelled Slurm job(s) %s; run the same command with --resume to resume\n",
                     job_list.c_str());
        std::exit(130);
      }
      // The tasks still queued or running, by JOBID_TASK.
      std::map<std::string, std::string> state;
      std::istringstream q(capture_shell("squeue -h -r -o '%i %t' -j " + shell_quote(job_list)));
      for (std::string id, st; q >> id >> st;) state[id] = st;
      // A signal during the poll: its answer may be cut short, and a task
      // missing from it would be taken as ended.
      if (g_interrupted) continue;
      int pending = 0, running = 0, failed = 0;
      for (Task& t : tasks_) {
        if (t.ended) {
          failed += runs_[t.run].rc != 0;
          continue;
        }
        PoolRun& r = runs_[t.run];
        const auto it = state.find(t.job);
        const bool has_code = fs::exists(r.dir + "/exit_code");
        if (it != state.end() && !has_code) {
          // A bundled run waits in a running task until its run.log appears.
          const bool queued = it->second == "PD" || (t.bundled && !fs::exists(r.dir + "/run.log"));
          (queued ? pending : running)++;
          if (!queued && !clocks_[t.run].running) clocks_[t.run].running = true, clocks_[t.run].start = Clock::now();
          continue;
        }
        t.ended = true, ++ended, ++done_;
        clocks_[t.run].ended = true, clocks_[t.run].running = false;
        failed += end_run(t, has_code) != 0;
      }
      if (!quiet_ && std::chrono::duration<double>(Clock::now() - last_report).count() >= 10) {
        std::printf("  slurm %s: %d pending, %d running, %zu done, %d failed, %.0f s elapsed\n", job_list.c_str(),
                    pending, running, ended, failed, elapsed());
        print_progress(runs_, clocks_, std::max(1, running), elapsed());
        last_report = Clock::now();
      }
      std::fflush(stdout);
    }
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }

  // A task's run has ended: its exit code and wall time from its folder, or
  // (none there) the task's Slurm state. Its exit code.
  int end_run(const Task& t, bool has_code) {
    PoolRun& r = runs_[t.run];
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
    if (!quiet_)
      std::printf("[%d/%zu] %s: %s in %.1f s (%.0f s elapsed)\n", done_, runs_.size(), r.label.c_str(), how.c_str(),
                  r.seconds, elapsed());
    return r.rc;
  }

  std::vector<PoolRun>& runs_;
  const SlurmOptions& o_;
  bool quiet_;
  std::string slurm_dir_;
  std::vector<RunClock> clocks_;
  int done_;
  std::vector<Task> tasks_;
  std::vector<std::string> jobs_;
  Clock::time_point t0_ = Clock::now();
};

// --runs-per-task auto (docs/cluster.md, "Bundled tasks"): the cheapest
// run (estimated_cost: planned steps x elements^1.5) goes first as a task
// of its own; its wall time t_p, scaled by the other runs' mean cost over
// its own, estimates a run's time t. N = floor(T / t) for tasks of T =
// kTaskTarget seconds (or half of --time, if less), at most ceil(M / C)
// (M runs left, C the partition's CPUs: every CPU can get a task), at
// least ceil(M / MaxArraySize) (the runs in one array) and 1.
constexpr double kTaskTarget = 300.0;  // s

EngineChoice choose_runs_per_task(const std::vector<PoolRun>& runs, const std::vector<std::size_t>& rest,
                                  const PoolRun& probe, const SlurmOptions& o) {
  EngineChoice c;
  c.engine = "slurm";
  c.rule = "auto";
  c.probe_run_s = probe.seconds;
  double mean_cost = 0;
  for (std::size_t i : rest) mean_cost += runs[i].cost;
  mean_cost /= std::max<std::size_t>(1, rest.size());
  c.estimated_run_s = probe.seconds * (probe.cost > 0 ? std::max(1.0, mean_cost / probe.cost) : 1.0);
  c.task_target_s = kTaskTarget;
  if (const double limit = slurm_seconds(o.time_limit); limit > 0) c.task_target_s = std::min(c.task_target_s, limit / 2);
  c.cpus = cluster_cpus(o.partition);
  const double m = static_cast<double>(rest.size());
  const double by_time = probe.rc >= 0 && c.estimated_run_s > 0 ? std::floor(c.task_target_s / c.estimated_run_s) : 1;
  const double fill = std::ceil(m / c.cpus), fit = std::ceil(m / max_array_size());
  c.runs_per_task = static_cast<int>(std::max({1.0, fit, std::min(by_time, fill)}));
  return c;
}

EngineChoice run_slurm(std::vector<PoolRun>& runs, const std::string& work_dir, const SlurmOptions& o, bool quiet) {
  int rc = 0;
  capture_shell("sbatch --version", &rc);
  if (rc != 0)
    throw InputError("--engine slurm: sbatch is not on PATH (scripts/slurm-local start gives a test cluster; "
                     "docs/cluster.md)");
  const std::string self = self_executable();
  const std::string slurm_dir = fs::absolute(work_dir + "/slurm").string();
  fs::create_directories(slurm_dir);
  // Kept from an earlier run of the same command (--resume): rc set.
  std::vector<std::size_t> todo;
  int done = 0;
  for (std::size_t i = 0; i < runs.size(); ++i) (runs[i].rc == 0 ? (void)++done : todo.push_back(i));
  EngineChoice choice;
  choice.engine = "slurm";
  choice.runs_per_task = std::max(1, o.runs_per_task);
  choice.rule = o.runs_per_task > 0 ? "given" : "auto";
  // Auto: the cheapest run first, alone (its time sets N for the rest).
  const bool probe = o.runs_per_task == 0 && todo.size() > 1;
  if (probe)
    std::stable_sort(todo.begin(), todo.end(), [&](std::size_t a, std::size_t b) { return runs[a].cost < runs[b].cost; });
  if (o.runs_per_task == 0 && !probe) choice.rule = "auto: one run";
  {
    std::vector<PoolRun> listed;
    std::ofstream cmds(slurm_dir + "/commands.txt"), sh(slurm_dir + "/array.sh");
    for (std::size_t i : todo) {
      PoolRun r = runs[i];
      r.dir = fs::absolute(r.dir).string();
      cmds << run_command(r, self) << "\n";
      listed.push_back(r);
      fs::remove(r.dir + "/exit_code");
      fs::remove(r.dir + "/exit_code.tmp");
      fs::remove(r.dir + "/run.log");  // a bundled run has started when its run.log appears
    }
    write_task_runs(slurm_dir + "/runs.txt", listed);
    sh << array_script(self, slurm_dir);
    if (!cmds || !sh) throw InputError("--engine slurm: cannot write to " + slurm_dir);
  }
  if (todo.empty()) {
    if (!quiet) std::printf("%zu runs on Slurm: 0 submitted, %d finished before (%s)\n", runs.size(), done, slurm_dir.c_str());
    return choice;
  }
  // The folder seen from a compute node: one short task writes a file
  // there, the same partition and account as the arrays (once per folder
  // and process: a calibration submits one run at a time).
  static std::set<std::string> shared;
  std::string where;
  if (!o.partition.empty()) where += " -p " + shell_quote(o.partition);
  if (!o.account.empty()) where += " -A " + shell_quote(o.account);
  if (!shared.count(slurm_dir + where)) {
    const std::string probe_file = slurm_dir + "/probe";
    fs::remove(probe_file);
    const std::string said = capture_shell("srun -N1 -n1 -t 1" + where + " touch " + shell_quote(probe_file), &rc);
    if (rc != 0 || !fs::exists(probe_file))
      throw InputError("--engine slurm: " + slurm_dir + " is not writable from a compute node (the output folder "
                       "must be on a filesystem the nodes share): " +
                       (said.empty() ? "a one-task srun ran but its file did not appear here" : said));
    fs::remove(probe_file);
    shared.insert(slurm_dir + where);
  }
  if (!quiet)
    std::printf("%zu runs on Slurm: %zu submitted, %d finished before (%s)\n", runs.size(), todo.size(), done,
                slurm_dir.c_str());
  SlurmArrays arrays(runs, o, quiet, slurm_dir, done);
  std::size_t from = 0;
  if (probe) {
    arrays.submit(todo, 0, 1, 1);
    arrays.wait();
    from = 1;
    choice = choose_runs_per_task(runs, std::vector<std::size_t>(todo.begin() + 1, todo.end()), runs[todo[0]], o);
    if (!quiet)
      std::printf("  runs per task: %d (auto: the probe run %.2f s, a run ~%.2f s, tasks of %.0f s, at most %zu "
                  "runs over %d CPUs)\n",
                  choice.runs_per_task, choice.probe_run_s, choice.estimated_run_s, choice.task_target_s,
                  (todo.size() - 1 + choice.cpus - 1) / choice.cpus, choice.cpus);
  }
  arrays.submit(todo, from, todo.size(), choice.runs_per_task);
  arrays.wait();
  return choice;
}

}  // namespace

EngineChoice run_runs(std::vector<PoolRun>& runs, const std::string& work_dir, const EngineOptions& engine,
                      int jobs, bool quiet) {
  for (auto& r : runs) r.rc = -1;
  if (engine.resume)
    for (auto& r : runs)
      if (const auto seconds = finished_before(r)) r.rc = 0, r.seconds = *seconds;
  if (engine.engine == "slurm") return run_slurm(runs, work_dir, engine.slurm, quiet);
  if (engine.engine != "local") throw InputError("--engine: '" + engine.engine + "' is unknown; expected local or slurm");
  run_pool(runs, jobs, quiet);
  EngineChoice local;
  local.engine = "local";
  return local;
}

}  // namespace rpfem
