#include "mesh_size_guard.hpp"

#include <algorithm>
#include <cmath>

#include "io/case_file.hpp"

namespace rpfem::fuzz {

namespace {

// A division count as the reader scales it, or 1 where it would refuse it.
double divisions(CaseSection& mesh, const std::string& key, int def, double factor) {
  try {
    return std::max(1.0, std::round(mesh.integer(key, def, 1, 100000) * factor));
  } catch (const InputError&) {
    return 1;
  }
}

double body_elements(CaseSection& mesh, double factor) {
  std::string shape;
  try {
    shape = mesh.text("shape", "");
  } catch (const InputError&) {
    return 0;
  }
  if (shape == "rectangle" || shape == "quadrilateral")
    return divisions(mesh, "nx", 1, factor) * divisions(mesh, "ny", 1, factor);
  if (shape == "ring") return divisions(mesh, "nr", 1, factor) * divisions(mesh, "ny", 1, factor);
  if (shape == "disk") {
    // Per quarter an n x n core and two layers x n blocks; "half" has two.
    const double n = divisions(mesh, "n", 8, factor), layers = divisions(mesh, "layers", 8, factor);
    bool half = true;
    try {
      half = mesh.text("part", "half") == "half";
    } catch (const InputError&) {
    }
    return (half ? 2 : 1) * (n * n + 2 * layers * n);
  }
  return 0;
}

}  // namespace

double mesh_elements(const std::string& case_file, const std::vector<std::string>& overrides) {
  try {
    CaseFile file(case_file, overrides);
    CaseSection root = file.root();
    double factor = 1;
    try {
      if (auto run = root.table("run")) factor = run->real("mesh_factor", 1.0, {0, 16, true, false});
    } catch (const InputError&) {
    }
    double total = 0;
    auto bodies = root.table("bodies");
    if (!bodies) return 0;
    for (const auto& name : bodies->keys()) {
      try {
        auto body = bodies->table(name);
        auto mesh = body ? body->table("mesh") : std::nullopt;
        if (mesh) total += body_elements(*mesh, factor);
      } catch (const InputError&) {  // not a table: no mesh
      }
    }
    return total;
  } catch (const InputError&) {
    return 0;
  }
}

}  // namespace rpfem::fuzz
