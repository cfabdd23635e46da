// The one place that turns a formulation keyword into an object (after IPC
// Toolkit's create_broad_phase): nowhere else switches on the keyword.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "io/case_file.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

struct FormulationInfo {
  std::string name;
  std::string help;
  bool dies = false;    // treats contact with rigid dies
  bool bodies = false;  // treats contact between deformable bodies
};
const std::vector<FormulationInfo>& formulations();
// The formulation of that name, nullptr if none.
const FormulationInfo* find_formulation(const std::string& name);
// The known names, comma-separated (for messages).
std::string formulation_names();

// Reads the formulation's own case keys from `file`; throws InputError for
// an unknown name or a combination the scene cannot use.
std::unique_ptr<ContactFormulation> make_formulation(const std::string& name, CaseFile& file, const Scene& scene);

}  // namespace rpfem
