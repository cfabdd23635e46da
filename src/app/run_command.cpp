#include "app/run_command.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "app/case_setup.hpp"
#include "app/linked_blas.hpp"
#include "app/output_folder.hpp"
#include "app/remeshing_run.hpp"
#include "app/run_observer.hpp"
#include "factory.hpp"
#include "io/variants.hpp"
#include "core/version.hpp"
#include "io/case_file.hpp"
#include "mesh/quality.hpp"

namespace rpfem {

namespace {

// One run: the case with the variant's overrides, then the user's.
int run_one(const RunOptions& opt, const Variant* variant, const std::string& out_dir) {
  make_output_folder(out_dir);
  std::vector<std::string> overrides;
  if (variant) overrides = variant->set;
  overrides.insert(overrides.end(), opt.overrides.begin(), opt.overrides.end());
  PreparedCase prepared = prepare_case(opt.case_file, overrides, opt.formulation, opt.discretization);
  const CaseFile& file = *prepared.file;
  Scene& scene = *prepared.scene;
  const std::vector<Monitor>& monitors = prepared.monitors;
  ContactFormulation* contact = prepared.contact.get();
  const ContactInfo info = contact->info();
  const std::string label = contact_label(info);

  const MeshQuality q = mesh_quality(scene.mesh);
  const int blas_threads = set_blas_threads(scene.solver.blas_threads);
  toml::table summary{{"case", scene.name},
                      {"case_file", std::filesystem::absolute(opt.case_file).string()},
                      {"variant", variant ? variant->name : std::string()},
                      {"formulation", label},
                      {"enforcement", info.enforcement},
                      {"discretization", info.discretization},
                      {"version", kVersion},
                      {"blas", linked_blas()},
                      {"blas_threads", blas_threads},
                      {"parameters", file.used()}};
  toml::array ov, user_set;
  for (const auto& o : overrides) ov.push_back(o);
  for (const auto& o : opt.overrides) user_set.push_back(o);
  summary.insert("overrides", ov);
  // The command line's own choices: what a resumed pool compares a
  // finished run with (app/run_engine.hpp).
  summary.insert("request", toml::table{{"case_file", std::filesystem::absolute(opt.case_file).string()},
                                        {"formulation", opt.formulation},
                                        {"discretization", opt.discretization},
                                        {"variant", variant ? variant->name : std::string()},
                                        {"set", user_set}});
  summary.insert("mesh", toml::table{{"nodes", scene.mesh.num_nodes()},
                                     {"elements", scene.mesh.num_elements()},
                                     {"min_scaled_jacobian", q.min_scaled_jacobian},
                                     {"max_aspect_ratio", q.max_aspect_ratio}});
  if (!opt.quiet)
    std::printf("rpfem %s: %s%s%s with '%s': %lld elements, %lld nodes, mesh quality: min scaled Jacobian %.3f, "
                "max aspect ratio %.2f\n",
                kVersion, scene.name.c_str(), variant ? ", variant " : "", variant ? variant->name.c_str() : "",
                label.c_str(), (long long)scene.mesh.num_elements(), (long long)scene.mesh.num_nodes(),
                q.min_scaled_jacobian, q.max_aspect_ratio);

  catch_interrupts();
  remove_run_results(out_dir);
  RunObserver obs(scene, out_dir, summary, opt.quiet, monitors);
  const RunOutcome out = run_with_remeshing(prepared, opt.formulation, opt.discretization, obs);
  obs.finish(out);
  std::fflush(stdout);  // the progress lines before the warnings and errors
  for (const auto& w : out.warnings) std::fprintf(stderr, "rpfem: warning: %s\n", w.c_str());
  if (out.interrupted) {
    const int signo = interrupt_signal();
    std::fprintf(stderr, "rpfem: %s: run %s (finished steps saved in %s)\n", signal_name(signo), out.reason.c_str(),
                 out_dir.c_str());
    return 128 + signo;
  }
  if (!out.finished) {
    std::fprintf(stderr, "rpfem: run stopped: %s (finished steps saved in %s)\n", out.reason.c_str(),
                 out_dir.c_str());
    return 3;
  }
  if (!opt.quiet) {
    const std::string discarded = out.discarded_newton_iterations > 0
                                      ? " (and " + std::to_string(out.discarded_newton_iterations) +
                                            " in attempts not kept)"
                                      : "";
    std::printf("finished: %d steps, %d Newton iterations%s; final load %s; %zu warning%s; results in %s\n",
                out.steps, out.total_newton_iterations, discarded.c_str(), obs.final_loads_text().c_str(),
                out.warnings.size(), out.warnings.size() == 1 ? "" : "s", out_dir.c_str());
  }
  return 0;
}

}  // namespace

int run_command(const RunOptions& opt) {
  // --force: each run removes its own files as it starts (and --variant
  // all the variant folders it no longer runs); nothing else here is the
  // run's to remove. Nothing recursive: a pool's run folder holds its
  // variants' folders, run at the same time, and the run.log being written.
  claim_output_folder(opt.out_dir, opt.force ? ExistingOutput::Keep : ExistingOutput::Refuse);
  if (opt.variant.empty()) return run_one(opt, nullptr, opt.out_dir);
  CaseFile probe(opt.case_file);
  const std::vector<Variant> variants = read_variants(probe.root());
  if (opt.variant != "all") return run_one(opt, &find_variant(variants, opt.variant, opt.case_file), opt.out_dir);
  if (variants.empty()) throw InputError(opt.case_file + ": --variant all: the case declares no [[variants]]");
  // The variants a previous run of this command left that the case no
  // longer declares.
  std::vector<std::string> names;
  for (const auto& v : variants) names.push_back(v.name);
  remove_stale_variant_runs(opt.out_dir, names);
  // Each variant into OUT/NAME; the worst exit code (2 bad input, 3 stopped).
  int worst = 0;
  std::vector<std::string> lines;
  for (const auto& v : variants) {
    const auto t0 = std::chrono::steady_clock::now();
    int rc;
    try {
      rc = run_one(opt, &v, (std::filesystem::path(opt.out_dir) / v.name).string());
    } catch (const InputError& e) {
      std::fprintf(stderr, "rpfem: error: variant %s: %s\n", v.name.c_str(), e.what());
      rc = 2;
    }
    if (rc > 128) return rc;  // interrupted: the other variants are not run
    if (rc == 2 || (rc == 3 && worst == 0)) worst = rc;
    char buf[160];
    std::snprintf(buf, sizeof buf, "  %-24s %-9s %8.1f s", v.name.c_str(),
                  rc == 0 ? "finished" : rc == 3 ? "stopped" : "bad input",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    lines.push_back(buf);
  }
  if (!opt.quiet) {
    std::printf("variants of %s (results in %s/NAME):\n", opt.case_file.c_str(), opt.out_dir.c_str());
    for (const auto& l : lines) std::printf("%s\n", l.c_str());
  }
  return worst;
}

}  // namespace rpfem
