// How deep a rigid die's corners reach into a body between its nodes.
// Node-to-segment contact keeps the body's nodes out of a die, not a die's
// corners out of the body's edges: where the body flows around a die
// corner, the corner sinks into the edge between two surface nodes and the
// volume it overlaps is lost to the contact. A remesh puts nodes along
// that edge, which the contact then keeps out (the remesh trigger
// remesh.die_interference).
#pragma once
#include <vector>

#include "model/scene.hpp"

namespace rpfem {

struct DieInterference {
  double depth = 0;     // mm, the deepest die point inside a body
  // That depth over the target element size there (the body's
  // remesh.size times remesh.die_corner_size: what a remesh puts there).
  double relative = 0;
  int die = -1, body = -1;
};

// The die points checked: every vertex of each die's profile and points
// along its arcs (every 10 degrees), at time t, against the outline of
// each body a contact pair joins to that die, at coordinates x.
DieInterference die_interference(const Scene& scene, const std::vector<Vec2>& x, double t);

}  // namespace rpfem
