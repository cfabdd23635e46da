#include "app/case_setup.hpp"

#include "expectations.hpp"
#include "factory.hpp"
#include "io/variants.hpp"
#include "io/scene_reader.hpp"
#include "model/boundary.hpp"
#include "model/remesh.hpp"

namespace rpfem {

PreparedCase prepare_case(const std::string& case_file, const std::vector<std::string>& overrides,
                          const std::string& formulation, const std::string& discretization) {
  PreparedCase c;
  c.file = std::make_unique<CaseFile>(case_file, overrides);
  read_variants(c.file->root());  // validated, and known to finish()
  validate_expect_tables(c.file->root(), case_file);  // the same ([expect], checked by verification/)
  c.scene = std::make_unique<Scene>(read_scene(*c.file));
  if (c.scene->remesh.enabled && c.scene->remesh.initial_mesh) *c.scene = initial_remesh(*c.scene);
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
