// A run with its remeshes: run_scene until it ends, or stops for a remesh
// (scene.remesh: the stepper only stops), then the bodies meshed anew at
// the last state (model/remesh.hpp), a new contact formulation made with
// the run's choice on the new scene, and the run resumed from the moved
// state; the observer writes one history and one result file throughout.
#pragma once
#include <string>

#include "app/case_setup.hpp"
#include "app/run_observer.hpp"

namespace rpfem {

// formulation, discretization: the run's contact choice (as prepare_case's).
RunOutcome run_with_remeshing(PreparedCase& c, const std::string& formulation, const std::string& discretization,
                              RunObserver& obs);

}  // namespace rpfem
