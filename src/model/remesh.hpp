// Remeshing bodies of a scene at a run's state, for the run to resume
// (model/stepper.hpp, RunState): each listed body's outline meshed anew at
// its current configuration (mesh/outline_mesher.hpp: the outline, its
// nodes and named sides kept), the other bodies as they are. Where an
// outline edge cut across a die's corner, its new points go onto the die
// and the volume so taken out is put back by moving the free surface (the
// boundary nodes off the dies, the axis and the symmetry planes) along its
// normal, uniformly (the remedy DEFORM calls TRGVOL); the state
// moved onto the new mesh: the effective strain by patch recovery and
// interpolation (mesh/field_transfer.hpp), the velocities interpolated (a
// start for Newton only). Velocity groups, tractions and contact pairs name
// sides, so they hold on the new mesh as they are.
#pragma once
#include <string>
#include <vector>

#include "mesh/field_transfer.hpp"
#include "model/scene.hpp"
#include "model/stepper.hpp"

namespace rpfem {

struct RemeshedScene {
  Scene scene;     // the scene with its mesh replaced; its coordinates are the state's
  RunState state;  // on the new mesh: the same time, stroke and step
  std::vector<Index> kept;  // per old node: the new node at its place (-1: an inner node remeshed away)
  // The volume the new outline's points took out of the dies' corners
  // (relative to the bodies' volume), put back on the free surface.
  double overlap_restored = 0;
  // The bodies whose new mesh gmsh's fallback subdivided (OutlineMesh).
  std::vector<std::string> subdivided;
};

// What a remesh changed (events.csv, summary.json): relative changes of the
// bodies' volume, of the integral of the effective strain over them, and of
// its largest value at a Gauss point.
struct RemeshChange {
  double volume = 0, strain_integral = 0, strain_max = 0;
};
RemeshChange remesh_change(const Scene& before, const RunState& old_state, const RemeshedScene& after);

struct RemeshRequest {
  std::vector<int> bodies;    // the bodies meshed anew
  std::vector<double> size;   // mm, the target element size of each
  double volume_tolerance = 0;  // per body, the share of its volume its outline's simplification may change
  // Near a die's corner (a sharp vertex or a fillet within one element size
  // of the body) the target size falls to this share of the body's, graded
  // back to it over four element sizes; 1: uniform.
  double die_corner_size = 1;
  // The size from the old mesh's strain-rate error
  // (model/error_size_field.hpp) at this target relative error, bounded to
  // min_size to max_size times the body's size, the smaller of it and the
  // corners' grading (that then stops at max_size); 0: off. Used where the
  // state has its strain rate (RunState::rate).
  double target_error = 0;
  double min_size = 0, max_size = 1;
  std::vector<Index> pinned;  // nodes of the scene's mesh that stay (monitored nodes)
};

RemeshedScene remesh_scene(const Scene& scene, const RunState& state, const RemeshRequest& request);

// The request of the scene's [remesh] (no pinned nodes).
RemeshRequest remesh_request(const Scene& scene);

// The scene with its remeshed bodies meshed anew in their initial
// configuration (remesh.initial_mesh): the same outline, the remesher's
// size field; with remesh.target_error, from the error of `rate`, the
// strain rate of a solve on the scene's mesh at the 2x2 points (empty:
// the corners' grading alone).
Scene initial_remesh(const Scene& scene, const std::vector<GaussValues>& rate = {});

}  // namespace rpfem
