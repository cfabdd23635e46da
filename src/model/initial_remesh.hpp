// The case's mesh replaced by the remesher's before a run
// (remesh.initial_mesh); implemented with the remesher (remesh.cpp).
#pragma once
#include "model/scene.hpp"

namespace rpfem {

// The scene with its remeshed bodies meshed anew in their initial
// configuration: the same outline, the remesher's size field.
Scene initial_remesh(const Scene& scene);

}  // namespace rpfem
