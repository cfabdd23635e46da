#include "app/case_setup.hpp"

#include "expectations.hpp"
#include "factory.hpp"
#include "io/variants.hpp"
#include "io/scene_reader.hpp"
#include "model/boundary.hpp"
#include "model/remesh.hpp"
#include "model/stepper.hpp"

namespace rpfem {

namespace {

// Stops a run after its first solve (step 0), recording nothing.
class FirstSolveOnly : public StepObserver {
 public:
  void on_step(const StepRecord&) override {}
  bool stop_requested() const override { return true; }
};

// remesh.initial_mesh: the bodies meshed anew before the first step. With
// remesh.target_error the size comes from the error of a first solve on
// the case's own mesh (step 0 under the run's contact choice); where that
// solve fails, from the dies' corners' grading alone (the run then meets
// the same first configuration and says why it fails there).
Scene initial_mesh(PreparedCase& c, const ContactChoice& choice) {
  if (!(c.scene->remesh.target_error > 0)) return initial_remesh(*c.scene);
  FirstSolveOnly quiet;
  const RunOutcome first = run_scene(*c.scene, *make_contact(*c.file, *c.scene, choice), quiet);
  return initial_remesh(*c.scene, first.last.rate);
}

}  // namespace

PreparedCase prepare_case(const std::string& case_file, const std::vector<std::string>& overrides,
                          const std::string& formulation, const std::string& discretization) {
  PreparedCase c;
  c.file = std::make_unique<CaseFile>(case_file, overrides);
  read_variants(c.file->root());  // validated, and known to finish()
  validate_expect_tables(c.file->root(), case_file);  // the same ([expect], checked by verification/)
  c.scene = std::make_unique<Scene>(read_scene(*c.file));
  if (c.scene->remesh.enabled && c.scene->remesh.initial_mesh)
    *c.scene = initial_mesh(c, {formulation, discretization});
  c.monitors = read_monitors(c.file->root(), c.scene->mesh);
  c.contact = make_contact(*c.file, *c.scene, {formulation, discretization});
  c.file->finish();
  return c;
}

std::vector<std::string> load_columns(const PreparedCase& c) {
  std::vector<std::string> names = KernelConstraints(*c.scene).load_names(), out;
  for (const auto& n : c.contact->info().load_names) names.push_back(n);
  for (const auto& n : names) out.insert(out.end(), {n + ".Fx", n + ".Fy"});
  return out;
}

}  // namespace rpfem
