#include "app/suite_command.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <toml++/toml.h>

#include "app/subprocess.hpp"
#include "app/variants.hpp"
#include "app/verify_command.hpp"
#include "core/types.hpp"
#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/result_writer.hpp"
#include "io/scene_reader.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

struct Job {
  std::string scene, case_file, formulation, variant, dir;
  double end_stroke = 0;  // mm
  int steps = 0;          // steps planned at the case's stroke increment
  int rc = -1;
  bool ended = false;
  double seconds = 0;
  std::chrono::steady_clock::time_point start;
};

// The formulations that treat every contact of the scene.
std::vector<std::string> applicable(const Scene& scene) {
  bool dies = false, bodies = false;
  for (const auto& p : scene.contact_pairs) (p.with_die() ? dies : bodies) = true;
  if (!dies && !bodies) return {scene.formulation};
  std::vector<std::string> out;
  for (const auto& f : formulations())
    if ((f.dies || !dies) && (f.bodies || !bodies) && (f.dies || f.bodies)) out.push_back(f.name);
  return out;
}

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

std::vector<Job> plan(const SuiteOptions& opt) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(opt.cases_dir))
    if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::string known;
  for (const auto& p : files) known += (known.empty() ? "" : ", ") + p.stem().string();
  for (const auto& s : opt.scenes)
    if (std::none_of(files.begin(), files.end(), [&](const fs::path& p) { return p.stem().string() == s; }))
      throw InputError(opt.cases_dir + ": no scene '" + s + "'; expected one of: " + known);
  for (const auto& f : opt.formulations)
    if (std::none_of(formulations().begin(), formulations().end(), [&](const auto& x) { return x.name == f; }))
      throw InputError("--formulation: '" + f + "' is unknown");
  std::vector<Job> jobs;
  for (const auto& path : files) {
    const std::string name = path.stem().string();
    if (!opt.scenes.empty() && std::find(opt.scenes.begin(), opt.scenes.end(), name) == opt.scenes.end()) continue;
    CaseFile file(path.string(), opt.overrides);
    const std::vector<Variant> variants = read_variants(file.root());
    const Scene scene = read_scene(file);
    for (const std::string& f : applicable(scene)) {
      if (!opt.formulations.empty() &&
          std::find(opt.formulations.begin(), opt.formulations.end(), f) == opt.formulations.end())
        continue;
      const std::string dir = opt.out_dir + "/" + name + "/" + f;
      const auto& st = scene.stepping;
      const int steps = std::max(1, static_cast<int>(std::ceil(st.end_stroke / st.stroke_increment - 1e-9)));
      auto add = [&](const std::string& variant, const std::string& d) {
        Job j;
        j.scene = name, j.case_file = path.string(), j.formulation = f, j.variant = variant, j.dir = d;
        j.end_stroke = st.end_stroke, j.steps = steps;
        jobs.push_back(j);
      };
      add("", dir);
      if (opt.variants && f == scene.formulation)
        for (const auto& v : variants) add(v.name, dir + "/" + v.name);
    }
  }
  return jobs;
}

// One line per run in flight (step k of n, stroke, Newton or Ipopt
// iterations of the last step, elapsed and estimated remaining time from
// the stroke done), and the suite's estimate: the runs in flight's
// remaining time plus the queued runs at the mean time of the finished
// ones (or of the running ones' projections), over the workers, and no
// less than the longest run in flight.
void print_progress(const std::vector<Job>& jobs, const std::vector<char>& running, int workers, double elapsed) {
  const auto now = std::chrono::steady_clock::now();
  double left = 0, longest = 0, finished_time = 0, projected = 0;
  int finished = 0, queued = 0, projections = 0;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const Job& j = jobs[i];
    if (j.ended) {
      finished_time += j.seconds, ++finished;
      continue;
    }
    if (!running[i]) {
      ++queued;
      continue;
    }
    const double run_s = std::chrono::duration<double>(now - j.start).count();
    const Progress p = read_progress(j.dir);
    const double frac = j.end_stroke > 0 ? std::min(1.0, p.stroke / j.end_stroke) : 0.0;
    std::printf("  running %s %s%s%s: ", j.scene.c_str(), j.formulation.c_str(), j.variant.empty() ? "" : " ",
                j.variant.c_str());
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
    std::printf("  suite: %d of %zu runs done, %.0f s elapsed, ~%.0f s left\n", finished, jobs.size(), elapsed,
                std::max(longest, (left + queued * mean) / std::max(1, workers)));
  std::fflush(stdout);
}

void write_manifest(const SuiteOptions& opt, const std::vector<Job>& jobs) {
  toml::array runs;
  for (const auto& j : jobs)
    runs.push_back(toml::table{{"case", j.scene}, {"case_file", fs::absolute(j.case_file).string()},
                               {"formulation", j.formulation}, {"variant", j.variant},
                               {"dir", fs::relative(j.dir, opt.out_dir).string()}, {"exit_code", j.rc},
                               {"wall_time_s", j.seconds}});
  std::ostringstream os;
  os << toml::json_formatter{toml::table{{"runs", runs}}} << "\n";
  write_text_atomically(opt.out_dir + "/suite.json", os.str());
}

}  // namespace

int suite_command(const SuiteOptions& options) {
  SuiteOptions opt = options;
  if (opt.quick) opt.overrides.insert(opt.overrides.begin(), "run.mesh_factor=0.5");
  if (!fs::is_directory(opt.cases_dir)) throw InputError(opt.cases_dir + ": no such cases folder");
  fs::create_directories(opt.out_dir);
  std::vector<Job> jobs = plan(opt);
  if (jobs.empty()) throw InputError(opt.cases_dir + ": no scene and formulation matched");
  const std::string self = self_executable();
  const int workers = std::max(1, opt.jobs > 0 ? opt.jobs : static_cast<int>(std::thread::hardware_concurrency()));
  std::atomic<std::size_t> next{0};
  std::atomic<int> done{0};
  std::mutex print;
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  std::vector<char> running(jobs.size(), 0);  // guarded by `print`, as the jobs' ends
  auto work = [&] {
    for (std::size_t i; (i = next++) < jobs.size();) {
      Job& j = jobs[i];
      fs::create_directories(j.dir);
      std::string cmd = shell_quote(self) + " run " + shell_quote(j.case_file) + " --out " + shell_quote(j.dir) + " --formulation " +
                        j.formulation + " --quiet";
      if (!j.variant.empty()) cmd += " --variant " + shell_quote(j.variant);
      for (const auto& o : opt.overrides) cmd += " --set " + shell_quote(o);
      cmd += " > " + shell_quote(j.dir + "/run.log") + " 2>&1";
      const auto s0 = std::chrono::steady_clock::now();
      {
        std::lock_guard<std::mutex> lock(print);
        j.start = s0;
        running[i] = 1;
      }
      const int rc = run_shell(cmd);
      std::lock_guard<std::mutex> lock(print);
      j.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      j.rc = rc;
      j.ended = true;
      const int k = ++done;
      running[i] = 0;
      if (!opt.quiet) {
        std::printf("[%d/%zu] %s %s%s%s: %s in %.1f s (%.0f s elapsed)\n", k, jobs.size(), j.scene.c_str(),
                    j.formulation.c_str(), j.variant.empty() ? "" : " ", j.variant.c_str(),
                    j.rc == 0 ? "finished" : ("stopped, exit " + std::to_string(j.rc)).c_str(), j.seconds, elapsed());
        std::fflush(stdout);
      }
    }
  };
  if (!opt.quiet) std::printf("rpfem suite: %zu runs on %d workers, results in %s\n", jobs.size(), workers, opt.out_dir.c_str());
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(work);
  // Progress of the runs in flight every 10 s (from their history.csv).
  while (done < static_cast<int>(jobs.size())) {
    for (int t = 0; t < 100 && done < static_cast<int>(jobs.size()); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (opt.quiet || done >= static_cast<int>(jobs.size())) continue;
    std::lock_guard<std::mutex> lock(print);
    print_progress(jobs, running, workers, elapsed());
  }
  for (auto& t : pool) t.join();
  write_manifest(opt, jobs);
  if (!opt.checks_file.empty()) {
    std::vector<std::string> scenes;
    for (const auto& j : jobs) scenes.push_back(j.scene);
    const int v = verify_command(opt.out_dir, opt.checks_file, true, scenes);
    if (!opt.quiet) std::printf("verification: %s (%s/verification.json)\n", v == 0 ? "every check passed" : "checks failed",
                                opt.out_dir.c_str());
  }
  int rc = 0;
  for (const auto& j : jobs)
    if (j.rc != 0) rc = 3;
  if (opt.report) {
    const std::string script = std::string(RPFEM_SOURCE_DIR) + "/reports/make_report.py";
    const std::string cmd = "/usr/bin/python3 " + shell_quote(script) + " " + shell_quote(opt.out_dir) +
                            " > /dev/null";
    if (std::system(cmd.c_str()) != 0) {
      std::fprintf(stderr, "rpfem suite: the report failed (%s)\n", cmd.c_str());
      return 3;
    }
    if (!opt.quiet) std::printf("report: %s\n", fs::absolute(opt.out_dir + "/report.html").string().c_str());
  }
  return rc;
}

}  // namespace rpfem
