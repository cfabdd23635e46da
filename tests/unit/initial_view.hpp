// A step view of a scene's initial configuration for the contact tests.
#pragma once
#include <vector>

#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem::unit {

// A step of 0.1 s from the scene's initial configuration, flow stress 300
// MPa everywhere (held in flow).
inline StepView initial_view(const Scene& scene, std::vector<double>& flow) {
  flow.assign(scene.mesh.num_elements(), 300.0);
  StepView v;
  v.mesh = &scene.mesh;
  v.x = v.x_from = &scene.mesh.x;
  v.flow_stress = &flow;
  v.geometry = scene.geometry;
  v.dt = 0.1;
  return v;
}

}  // namespace rpfem::unit
