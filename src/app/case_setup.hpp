// A case read and validated as `rpfem run` reads it: the file with its
// overrides, the scene, the monitors, the contact formulation, and every
// key checked as known (CaseFile::finish). `rpfem calibrate` prepares its
// case the same way before any run, so a bad key or value stops it at once.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "io/case_file.hpp"
#include "io/monitors.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

struct PreparedCase {
  // Held by pointer: the formulation may keep references into the file and
  // the scene.
  std::unique_ptr<CaseFile> file;
  std::unique_ptr<Scene> scene;
  std::vector<Monitor> monitors;
  std::unique_ptr<ContactFormulation> contact;
};

// formulation ("ENFORCEMENT" or "ENFORCEMENT+DISCRETIZATION") and
// discretization empty: the scene's own. Throws InputError.
PreparedCase prepare_case(const std::string& case_file, const std::vector<std::string>& overrides,
                          const std::string& formulation, const std::string& discretization = "");

// The load columns its history.csv will have: NAME.Fx and NAME.Fy for every
// velocity group and every load the formulation reports (its dies).
std::vector<std::string> load_columns(const PreparedCase& c);

}  // namespace rpfem
