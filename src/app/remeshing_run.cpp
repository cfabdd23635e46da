#include "app/remeshing_run.hpp"

#include <memory>
#include <vector>

#include "factory.hpp"
#include "model/remesh.hpp"

namespace rpfem {

namespace {

// Each body's target element size: remesh.element_size, else the body's
// mean edge length on the initial mesh.
std::vector<double> element_sizes(const Scene& s) {
  std::vector<double> total(s.mesh.num_bodies(), 0.0);
  std::vector<int> count(s.mesh.num_bodies(), 0);
  for (Index e = 0; e < s.mesh.num_elements(); ++e)
    for (int i = 0; i < 4; ++i) {
      total[s.mesh.element_body[e]] += (s.mesh.x[s.mesh.quads[e][(i + 1) % 4]] - s.mesh.x[s.mesh.quads[e][i]]).norm();
      ++count[s.mesh.element_body[e]];
    }
  std::vector<double> size(total.size());
  for (std::size_t b = 0; b < size.size(); ++b)
    size[b] = s.remesh.element_size > 0 ? s.remesh.element_size : total[b] / std::max(1, count[b]);
  return size;
}

// The totals of a resumed run added to the run so far.
void add(RunOutcome& run, const RunOutcome& more) {
  run.last = more.last;
  run.finished = more.finished;
  run.reason = more.reason;
  run.remesh = more.remesh;
  run.steps = more.steps;
  run.total_newton_iterations += more.total_newton_iterations;
  run.total_cuts += more.total_cuts;
  run.assembly_seconds += more.assembly_seconds, run.analyze_seconds += more.analyze_seconds;
  run.factor_seconds += more.factor_seconds, run.solve_seconds += more.solve_seconds;
  run.pattern_builds += more.pattern_builds, run.factorizations += more.factorizations;
  run.cholesky_fallbacks += more.cholesky_fallbacks;
  run.min_tangent_rcond = std::min(run.min_tangent_rcond, more.min_tangent_rcond);
  run.warnings.insert(run.warnings.end(), more.warnings.begin(), more.warnings.end());
}

}  // namespace

RunOutcome run_with_remeshing(PreparedCase& c, const std::string& formulation, const std::string& discretization,
                              RunObserver& obs) {
  RunOutcome out = run_scene(*c.scene, *c.contact, obs);
  if (out.remesh.empty()) return out;
  const std::vector<double> size = element_sizes(*c.scene);
  std::vector<int> bodies(c.scene->mesh.num_bodies());
  for (int b = 0; b < static_cast<int>(bodies.size()); ++b) bodies[b] = b;
  // The scenes and formulations of the segments stay alive to the end (a
  // formulation keeps references into its scene).
  std::vector<std::unique_ptr<Scene>> scenes;
  std::vector<std::unique_ptr<ContactFormulation>> contacts;
  const Scene* current = c.scene.get();
  for (int remeshes = 0; !out.finished && !out.remesh.empty(); ++remeshes) {
    if (remeshes == current->remesh.max_remeshes) {
      out.reason = "stopped for a remesh (" + out.remesh + ") after remesh.max_remeshes = " +
                   std::to_string(remeshes) + " remeshes";
      break;
    }
    RemeshedScene re;
    try {
      re = remesh_scene(*current, out.last, bodies, size);
    } catch (const std::exception& e) {
      out.reason = "remeshing at step " + std::to_string(out.last.step) + " failed: " + e.what();
      break;
    }
    obs.remeshed(re, out.remesh, remesh_change(*current, out.last, re));
    scenes.push_back(std::make_unique<Scene>(std::move(re.scene)));
    current = scenes.back().get();
    contacts.push_back(make_contact(*c.file, *current, {formulation, discretization}));
    add(out, run_scene(*current, *contacts.back(), obs, &re.state));
  }
  return out;
}

}  // namespace rpfem
