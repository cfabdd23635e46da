#include "app/run_command.hpp"

#include <cstdio>
#include <filesystem>

#include "app/run_observer.hpp"
#include "core/version.hpp"
#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "mesh/quality.hpp"

namespace rpfem {

int run_command(const RunOptions& opt) {
  CaseFile file(opt.case_file, opt.overrides);
  Scene scene = read_scene(file);
  const std::string fname = opt.formulation.empty() ? scene.formulation : opt.formulation;
  auto contact = make_formulation(fname, file, scene);
  file.finish();

  const MeshQuality q = mesh_quality(scene.mesh);
  toml::table summary{{"case", scene.name},
                      {"case_file", std::filesystem::absolute(opt.case_file).string()},
                      {"formulation", contact->name()},
                      {"version", kVersion},
                      {"parameters", file.used()}};
  toml::array overrides;
  for (const auto& o : opt.overrides) overrides.push_back(o);
  summary.insert("overrides", overrides);
  summary.insert("mesh", toml::table{{"nodes", scene.mesh.num_nodes()},
                                     {"elements", scene.mesh.num_elements()},
                                     {"min_scaled_jacobian", q.min_scaled_jacobian},
                                     {"max_aspect_ratio", q.max_aspect_ratio}});
  if (!opt.quiet)
    std::printf("rpfem %s: %s with '%s': %lld elements, %lld nodes, mesh quality: min scaled Jacobian %.3f, "
                "max aspect ratio %.2f\n",
                kVersion, scene.name.c_str(), contact->name().c_str(), (long long)scene.mesh.num_elements(),
                (long long)scene.mesh.num_nodes(), q.min_scaled_jacobian, q.max_aspect_ratio);

  RunObserver obs(scene, opt.out_dir, summary, opt.quiet);
  const RunOutcome out = run_scene(scene, *contact, obs);
  obs.finish(out);
  if (!out.finished) {
    std::fprintf(stderr, "rpfem: run stopped: %s (finished steps saved in %s)\n", out.reason.c_str(),
                 opt.out_dir.c_str());
    return 3;
  }
  if (!opt.quiet)
    std::printf("finished: %d steps, %d Newton iterations; results in %s\n", out.steps,
                out.total_newton_iterations, opt.out_dir.c_str());
  return 0;
}

}  // namespace rpfem
