#include "contact/friction_treatment.hpp"

#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

namespace {

void check(const Scene& scene, const std::string& name, const FrictionTreatments& can, const FrictionLaw& law,
           const std::string& table) {
  if (law.kind == FrictionLaw::Kind::None) return;
  const bool exact = law.exact(can.exact_by_default);
  if (exact ? can.exact : can.arctan) return;
  throw InputError(scene.file + ": " + table + ".regularization = \"" + (exact ? "exact" : "arctan") +
                   "\": enforcement '" + name + "' treats friction " + (exact ? "by the arctan law only" : "exactly only") +
                   "; expected \"" + (exact ? "arctan" : "exact") + "\", or another enforcement");
}

}  // namespace

void require_friction_treatment(const Scene& scene, const std::string& name, FrictionTreatments can) {
  for (const auto& d : scene.dies) check(scene, name, can, d.friction, "dies." + d.name + ".friction");
  for (std::size_t i = 0; i < scene.contact_pairs.size(); ++i)
    if (!scene.contact_pairs[i].with_die())
      check(scene, name, can, scene.contact_pairs[i].friction, "contact_pairs[" + std::to_string(i) + "].friction");
}

}  // namespace rpfem
