#include "factory.hpp"

#include "direct/direct_formulation.hpp"
#include "ipopt/ipopt_formulation.hpp"
#include "none/none_formulation.hpp"
#include "penalty/penalty_formulation.hpp"

namespace rpfem {

const std::vector<FormulationInfo>& formulations() {
  static const std::vector<FormulationInfo> list{
      {"none", "no contact: platens as prescribed velocities, tractions, symmetry planes", false, false},
      {"direct", "rigid dies as kinematic constraints (ALPID): exact normal velocity, free sliding", true, false},
      {"penalty", "node-to-segment penalty on the normal relative velocity, between bodies and against dies (the paper)",
       true, true},
      {"ipopt", "each step a constrained minimization solved by Ipopt: the Kuhn-Tucker contact conditions to solver tolerance",
       true, true},
  };
  return list;
}

const FormulationInfo* find_formulation(const std::string& name) {
  for (const auto& f : formulations())
    if (f.name == name) return &f;
  return nullptr;
}

std::string formulation_names() {
  std::string known;
  for (const auto& f : formulations()) known += (known.empty() ? "" : ", ") + f.name;
  return known;
}

std::unique_ptr<ContactFormulation> make_formulation(const std::string& name, CaseFile& file, const Scene& scene) {
  // Each formulation reads [formulations.<name>]; the others' sections are
  // known keys that this run does not use.
  CaseSection all = file.root().section("formulations");
  for (const auto& f : formulations())
    if (f.name != name) all.ignore(f.name);
  if (name == "none") {
    if (!scene.contact_pairs.empty())
      throw InputError(file.path() + ": the scene declares contact pairs; formulation 'none' treats no contact");
    return std::make_unique<NoContact>();
  }
  if (name == "direct") return std::make_unique<DirectContact>(scene, all.section("direct"));
  if (name == "penalty") return std::make_unique<PenaltyContact>(scene, all.section("penalty"));
  if (name == "ipopt") return std::make_unique<IpoptContact>(scene, all.section("ipopt"));
  throw InputError(file.path() + ": formulation '" + name + "' is unknown; expected one of: " + formulation_names());
}

}  // namespace rpfem
