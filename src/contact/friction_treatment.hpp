// Which friction treatment an enforcement takes (material/friction_law.hpp,
// `regularization`): the arctan law, the exact law, or both. A scene whose
// friction table asks for one the enforcement cannot do is refused at
// input, naming the key.
#pragma once
#include <string>

namespace rpfem {

struct Scene;

struct FrictionTreatments {
  bool arctan = true, exact = false;
  bool exact_by_default = false;  // the key unset means exact
};

// Throws InputError naming the scene's file, the friction table's key and
// what the enforcement `name` accepts.
void require_friction_treatment(const Scene& scene, const std::string& name, FrictionTreatments can);

}  // namespace rpfem
