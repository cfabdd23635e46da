// An element's material as the step's problem and the stepper read it:
// its flow stress law and the run's numerical parameters for it.
#pragma once
#include "material/flow_stress.hpp"

namespace rpfem {

struct ElementMaterial {
  const FlowStressLaw* law = nullptr;
  double alpha = 0;           // volumetric penalty, MPa s
  double regularization = 0;  // s, see RigidPlasticInput::regularization
};

}  // namespace rpfem
