#include "app/remeshing_run.hpp"

#include <memory>
#include <sstream>
#include <vector>

#include "factory.hpp"
#include "model/remesh.hpp"

namespace rpfem {

namespace {

// The totals of a resumed run added to the run so far.
void add(RunOutcome& run, const RunOutcome& more) {
  run.last = more.last;
  run.finished = more.finished;
  run.reason = more.reason;
  run.remesh = more.remesh;
  run.steps = more.steps;
  run.total_newton_iterations += more.total_newton_iterations;
  run.discarded_newton_iterations += more.discarded_newton_iterations;
  run.total_cuts += more.total_cuts;
  run.step_rejections += more.step_rejections;
  run.retunes += more.retunes;
  run.assembly_seconds += more.assembly_seconds, run.analyze_seconds += more.analyze_seconds;
  run.factor_seconds += more.factor_seconds, run.solve_seconds += more.solve_seconds;
  run.residual_seconds += more.residual_seconds, run.contact_seconds += more.contact_seconds;
  run.pattern_builds += more.pattern_builds, run.factorizations += more.factorizations;
  run.tangent_passes += more.tangent_passes, run.tangents_from_trials += more.tangents_from_trials;
  run.force_passes += more.force_passes, run.force_passes_reused += more.force_passes_reused;
  run.cholesky_fallbacks += more.cholesky_fallbacks;
  run.by_cholmod += more.by_cholmod, run.by_klu += more.by_klu, run.by_umfpack += more.by_umfpack;
  run.min_tangent_rcond = std::min(run.min_tangent_rcond, more.min_tangent_rcond);
  run.warnings.insert(run.warnings.end(), more.warnings.begin(), more.warnings.end());
}

// Remeshes that, kStallRemeshes in a row, advance the stroke by less than
// one step's increment in all end the run: each new mesh falls below
// remesh.reject_below within its first step, whose halvings take it a
// 64th of an increment, and the remesher is asked again
// (docs/decisions.md, "Remeshing": on subdivided meshes the remeshed ring
// at 72 x 48 crawled through 17 remeshes of 30,000 elements, 1e-3 mm
// each, and max_remeshes' 100 would have taken hours).
constexpr int kStallRemeshes = 5;

// The least advance kStallRemeshes remeshes in a row must make, mm: the
// step's nominal increment, or under step control its least.
double stall_advance(const Scene& scene, double stroke) {
  const SteppingSpec& sp = scene.stepping;
  return sp.tolerance > 0 && sp.min_increment > 0 ? sp.min_increment : sp.increment_at(stroke);
}

}  // namespace

RunOutcome run_with_remeshing(PreparedCase& c, const std::string& formulation, const std::string& discretization,
                              RunObserver& obs) {
  RunOutcome out = run_scene(*c.scene, *c.contact, obs);
  if (out.remesh.empty()) return out;
  RemeshRequest request = remesh_request(*c.scene);
  // The scenes and formulations of the segments stay alive to the end (a
  // formulation keeps references into its scene).
  std::vector<std::unique_ptr<Scene>> scenes;
  std::vector<std::unique_ptr<ContactFormulation>> contacts;
  const Scene* current = c.scene.get();
  const ContactFormulation* contact = c.contact.get();
  std::vector<double> strokes;  // the stroke of each remesh, mm
  for (int remeshes = 0; !out.finished && !out.remesh.empty(); ++remeshes) {
    if (remeshes == current->remesh.max_remeshes) {
      out.reason = "stopped for a remesh (" + out.remesh + ") after remesh.max_remeshes = " +
                   std::to_string(remeshes) + " remeshes";
      break;
    }
    strokes.push_back(out.last.stroke);
    if (strokes.size() > kStallRemeshes) {
      const double from = strokes[strokes.size() - 1 - kStallRemeshes], advance = out.last.stroke - from;
      const double least = stall_advance(*current, from);
      if (advance < least) {
        std::ostringstream why;
        why << "remeshing does not advance: the last " << kStallRemeshes << " remeshes took the stroke from " << from
            << " to " << out.last.stroke << " mm, less than one step's increment (" << least
            << " mm), each new mesh falling below remesh.reject_below = " << current->remesh.reject_below
            << " within its first steps (last: " << out.remesh
            << "); mesh finer (remesh.element_size) or allow more distortion (remesh.reject_below)";
        out.reason = why.str();
        break;
      }
    }
    RemeshedScene re;
    try {
      request.pinned = obs.pinned_nodes();
      re = remesh_scene(*current, out.last, request);
    } catch (const std::exception& e) {
      out.reason = "remeshing at step " + std::to_string(out.last.step) + " failed: " + e.what();
      break;
    }
    obs.remeshed(re, out.remesh, remesh_change(*current, out.last, re));
    const ContactZones zones = contact->contact_zones(out.last.x);
    scenes.push_back(std::make_unique<Scene>(std::move(re.scene)));
    current = scenes.back().get();
    contacts.push_back(make_contact(*c.file, *current, {formulation, discretization}));
    contacts.back()->take_over(zones);
    contact = contacts.back().get();
    add(out, run_scene(*current, *contacts.back(), obs, &re.state));
  }
  return out;
}

}  // namespace rpfem
