#include "app/suite_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "app/run_pool.hpp"
#include "app/subprocess.hpp"
#include "io/variants.hpp"
#include "app/verify_command.hpp"
#include "core/types.hpp"
#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/result_writer.hpp"
#include "io/scene_reader.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

using Job = PoolRun;

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
        j.label = name + " " + f + (variant.empty() ? "" : " " + variant);
        j.case_name = name, j.case_file = path.string(), j.formulation = f, j.variant = variant, j.dir = d;
        j.overrides = opt.overrides;
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

void write_manifest(const SuiteOptions& opt, const std::vector<Job>& jobs) {
  toml::array runs;
  for (const auto& j : jobs)
    runs.push_back(toml::table{{"case", j.case_name}, {"case_file", fs::absolute(j.case_file).string()},
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
  if (!opt.quiet) std::printf("rpfem suite: results in %s\n", opt.out_dir.c_str());
  run_pool(jobs, opt.jobs, opt.quiet);
  write_manifest(opt, jobs);
  if (!opt.checks_file.empty()) {
    std::vector<std::string> scenes;
    for (const auto& j : jobs) scenes.push_back(j.case_name);
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
