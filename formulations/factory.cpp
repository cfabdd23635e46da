#include "factory.hpp"

#include "none/none_formulation.hpp"

namespace rpfem {

const std::vector<FormulationInfo>& formulations() {
  static const std::vector<FormulationInfo> list{
      {"none", "no contact: platens as prescribed velocities, tractions, symmetry planes"},
  };
  return list;
}

std::unique_ptr<ContactFormulation> make_formulation(const std::string& name, CaseFile& file, const Scene& scene) {
  if (name == "none") return std::make_unique<NoContact>();
  std::string known;
  for (const auto& f : formulations()) known += (known.empty() ? "" : ", ") + f.name;
  throw InputError(file.path() + ": formulation '" + name + "' is unknown; expected one of: " + known);
}

}  // namespace rpfem
