// Turns a validated case file into a Scene: the kernel's part of the case
// (run, bodies, symmetry, solver, stepping). Contact sections are left to
// the formulation factory, which reads them from the same CaseFile.
// Keys, units and defaults: docs/case-format.md.
#pragma once
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

Scene read_scene(CaseFile& file);

}  // namespace rpfem
