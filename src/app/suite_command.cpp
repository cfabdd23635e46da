#include "app/suite_command.hpp"
#include "app/output_folder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <toml++/toml.h>

#include "app/case_folder.hpp"
#include "app/data_dir.hpp"
#include "app/linked_blas.hpp"
#include "app/run_engine.hpp"
#include "app/subprocess.hpp"
#include "app/suite_studies.hpp"
#include "io/variants.hpp"
#include "app/verify_command.hpp"
#include "core/types.hpp"
#include "core/version.hpp"
#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/result_writer.hpp"
#include "io/scene_reader.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

using Job = PoolRun;

// The combinations that treat every contact of the scene: each enforcement
// that applies with the scene's discretization (labelled by the
// enforcement alone), and with every other discretization that differs
// from it there (ENFORCEMENT+DISCRETIZATION), except one that over-constrains
// (two pass) under an exact enforcement (FormulationInfo::exact).
std::vector<std::string> applicable(CaseFile& file, const Scene& scene) {
  bool dies = false, bodies = false;
  for (const auto& p : scene.contact_pairs) (p.with_die() ? dies : bodies) = true;
  if (!dies && !bodies) return {scene.formulation};
  const std::string own = contact_choice(file, scene).discretization;
  // An enforcement that refuses over-constrained rows between bodies runs
  // only the other discretizations there.
  const auto allowed = [&](const FormulationInfo& f, const DiscretizationInfo& d) {
    return !(bodies && d.overconstrains && f.refuses_overconstrained);
  };
  std::vector<const FormulationInfo*> enforcements;
  for (const auto& f : formulations())
    if ((f.dies || !dies) && (f.bodies || !bodies) && (f.dies || f.bodies)) enforcements.push_back(&f);
  std::vector<std::string> out;
  for (const FormulationInfo* f : enforcements)
    if (allowed(*f, *find_discretization(own))) out.push_back(f->name);
  for (const auto& d : discretizations())
    if (d.name != own && (bodies || !d.between_bodies_only))
      for (const FormulationInfo* f : enforcements)
        if (!(d.overconstrains && f->exact)) out.push_back(f->name + "+" + d.name);
  return out;
}

std::vector<Job> plan(const SuiteOptions& opt) {
  const std::vector<fs::path> files = case_files(opt.cases_dir, opt.scenes, "scene");
  for (const auto& f : opt.formulations)
    if (!find_formulation(f))
      throw InputError("--formulation: '" + f + "' is unknown; expected one of: " + formulation_names());
  std::vector<Job> jobs;
  for (const auto& path : files) {
    const std::string name = path.stem().string();
    if (!opt.scenes.empty() && std::find(opt.scenes.begin(), opt.scenes.end(), name) == opt.scenes.end()) continue;
    CaseFile file(path.string(), opt.overrides);
    const std::vector<Variant> variants = read_variants(file.root());
    const Scene scene = read_scene(file);
    std::vector<std::string> formulations = applicable(file, scene);
    if (!scene.suite_formulations.empty()) {
      for (const std::string& f : scene.suite_formulations)
        if (std::find(formulations.begin(), formulations.end(), f) == formulations.end()) {
          std::string all;
          for (const std::string& a : formulations) all += (all.empty() ? "" : ", ") + a;
          throw InputError(path.string() + ": key 'run.suite_formulations': '" + f +
                           "' does not treat this scene's contacts; expected some of: " + all);
        }
      formulations = scene.suite_formulations;
    }
    for (const std::string& f : formulations) {
      if (!opt.formulations.empty() &&
          std::find(opt.formulations.begin(), opt.formulations.end(), f) == opt.formulations.end())
        continue;
      const std::string dir = opt.out_dir + "/" + name + "/" + f;
      const auto& st = scene.stepping;
      auto add = [&](const std::string& variant, const std::string& d) {
        Job j;
        j.label = name + " " + f + (variant.empty() ? "" : " " + variant);
        j.case_name = name, j.case_file = path.string(), j.formulation = f, j.variant = variant, j.dir = d;
        j.overrides = opt.overrides;
        j.end_stroke = st.end_stroke, j.steps = st.planned_steps();
        j.cost = estimated_cost(j.steps, scene.mesh.num_elements());
        jobs.push_back(j);
      };
      add("", dir);
      if (opt.variants && f == scene.formulation)
        for (const auto& v : variants) add(v.name, dir + "/" + v.name);
    }
  }
  return jobs;
}

void write_manifest(const SuiteOptions& opt, const std::vector<Job>& jobs, const std::vector<SweepPlan>& studies,
                    const std::vector<int>& stopped) {
  toml::array runs, study_list;
  for (const auto& j : jobs)
    runs.push_back(toml::table{{"case", j.case_name}, {"case_file", fs::absolute(j.case_file).string()},
                               {"formulation", j.formulation}, {"variant", j.variant},
                               {"dir", fs::relative(j.dir, opt.out_dir).string()}, {"exit_code", j.rc},
                               {"wall_time_s", j.seconds}});
  for (std::size_t i = 0; i < studies.size(); ++i) {
    const SweepPlan& p = studies[i];
    const std::string dir = fs::relative(p.options.out_dir, opt.out_dir).string();
    double seconds = 0;
    for (const auto& r : p.runs) seconds += r.seconds;
    toml::table t{{"study", p.study.name},
                  {"study_file", fs::absolute(p.study.file).string()},
                  {"case", fs::path(p.study.case_file).stem().string()},
                  {"description", p.study.description},
                  {"quick", p.options.quick},
                  {"dir", dir},
                  {"table", dir + "/sweep.csv"},
                  {"table_h5", dir + "/sweep.h5"},
                  {"metadata", dir + "/sweep.json"},
                  {"runs", static_cast<int64_t>(p.index.size())},
                  {"stopped", stopped[i]},
                  {"runs_time_s", seconds}};
    if (has_reference_run(p.study)) t.insert("reference_exit_code", p.runs.back().rc);
    study_list.push_back(t);
  }
  std::ostringstream os;
  // The program that ran the suite, for the report's provenance: the
  // executable, version, compiler and the BLAS it runs on.
#if defined(__clang__)
  const std::string compiler = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  const std::string compiler = std::string("GCC ") + __VERSION__;
#else
  const std::string compiler = "unknown";
#endif
  const toml::table program{
      {"path", self_executable()}, {"version", kVersion}, {"compiler", compiler}, {"blas", linked_blas()}};
  os << toml::json_formatter{toml::table{{"program", program}, {"runs", runs}, {"studies", study_list}}} << "\n";
  write_text_atomically(opt.out_dir + "/suite.json", os.str());
}

}  // namespace

int suite_command(const SuiteOptions& options) {
  SuiteOptions opt = options;
  if (opt.quick) opt.overrides.insert(opt.overrides.begin(), "run.mesh_factor=0.5");
  if (!fs::is_directory(opt.cases_dir)) throw InputError(opt.cases_dir + ": no such cases folder");
  claim_output_folder(opt.out_dir, existing_output(opt.force, opt.engine.resume), true);
  std::vector<Job> jobs = plan(opt);
  if (jobs.empty()) throw InputError(opt.cases_dir + ": no scene and formulation matched");
  // Variant runs a previous suite left under a run this one redoes (its
  // variants gone from the case, or --no-variants now).
  std::map<std::string, std::vector<std::string>> variants_of;
  for (const auto& j : jobs) {
    if (j.variant.empty()) variants_of[j.dir];
    else variants_of[fs::path(j.dir).parent_path().string()].push_back(j.variant);
  }
  for (const auto& [dir, keep] : variants_of) remove_stale_variant_runs(dir, keep);
  std::vector<SweepPlan> studies = plan_studies(opt);
  if (!opt.quiet) {
    std::printf("rpfem suite: results in %s\n", opt.out_dir.c_str());
    for (const auto& p : studies)
      std::printf("  study %s: %zu runs into %s\n", p.study.name.c_str(), p.runs.size(), p.options.out_dir.c_str());
  }
  // One pool for the scenes' runs and the studies': --jobs holds for all.
  std::vector<Job> all = jobs;
  for (const auto& p : studies) all.insert(all.end(), p.runs.begin(), p.runs.end());
  const EngineChoice engine = run_runs(all, opt.out_dir, opt.engine, opt.jobs, opt.quiet);
  std::copy_n(all.begin(), jobs.size(), jobs.begin());
  auto next = all.begin() + static_cast<std::ptrdiff_t>(jobs.size());
  std::vector<int> stopped;
  for (auto& p : studies) {
    std::copy_n(next, p.runs.size(), p.runs.begin());
    next += static_cast<std::ptrdiff_t>(p.runs.size());
    p.engine = engine;
    stopped.push_back(write_sweep(p));
  }
  write_manifest(opt, jobs, studies, stopped);
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
  // A study's run that stops is a measurement its table records (the
  // penalty studies look for where runs stop); its reference run is not.
  int study_stops = 0;
  for (std::size_t i = 0; i < studies.size(); ++i) {
    study_stops += stopped[i];
    if (has_reference_run(studies[i].study) && studies[i].runs.back().rc != 0) rc = 3;
  }
  if (!opt.quiet && study_stops > 0)
    std::printf("studies: %d run%s stopped early, recorded in the tables (the exit code does not count them)\n",
                study_stops, study_stops == 1 ? "" : "s");
  if (opt.report) {
    const std::string script = data_dir() + "/reports/make_report.py";
    const std::string cmd = "/usr/bin/python3 " + shell_quote(script) + " " + shell_quote(opt.out_dir) +
                            " > /dev/null";
    if (run_shell(cmd) != 0) {
      std::fprintf(stderr, "rpfem suite: the report failed (%s)\n", cmd.c_str());
      return 3;
    }
    if (!opt.quiet) std::printf("report: %s\n", fs::absolute(opt.out_dir + "/report.html").string().c_str());
  }
  return rc;
}

}  // namespace rpfem
