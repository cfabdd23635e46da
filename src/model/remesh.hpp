// Remeshing bodies of a scene at a run's state, for the run to resume
// (model/stepper.hpp, RunState): each listed body's outline meshed anew at
// its current configuration (mesh/outline_mesher.hpp: the outline, its
// nodes and named sides kept), the other bodies as they are; the state
// moved onto the new mesh: the effective strain by patch recovery and
// interpolation (mesh/field_transfer.hpp), the velocities interpolated (a
// start for Newton only). Velocity groups, tractions and contact pairs name
// sides, so they hold on the new mesh as they are.
#pragma once
#include <vector>

#include "model/scene.hpp"
#include "model/stepper.hpp"

namespace rpfem {

struct RemeshedScene {
  Scene scene;     // the scene with its mesh replaced; its coordinates are the state's
  RunState state;  // on the new mesh: the same time, stroke and step
  std::vector<Index> kept;  // per old node: the new node at its place (-1: an inner node remeshed away)
};

// What a remesh changed (events.csv, summary.json): relative changes of the
// bodies' volume, of the integral of the effective strain over them, and of
// its largest value at a Gauss point.
struct RemeshChange {
  double volume = 0, strain_integral = 0, strain_max = 0;
};
RemeshChange remesh_change(const Scene& before, const RunState& old_state, const RemeshedScene& after);

// size: the target element size per listed body (mm).
RemeshedScene remesh_scene(const Scene& scene, const RunState& state, const std::vector<int>& bodies,
                           const std::vector<double>& size);

}  // namespace rpfem
