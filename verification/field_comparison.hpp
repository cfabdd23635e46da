// Comparing two runs' fields on corresponding elements and nodes (paper
// Test I: the double-action spheres mirrored onto each other, and each onto
// the single-action sphere). Correspondence by the initial positions: each
// selected element (node) of run A is matched to the element (node) of run B
// whose initial centroid (position) is the mapped one, to 1e-9 mm.
#pragma once
#include <functional>
#include <string>

#include "core/types.hpp"

namespace rpfem {

enum class PointMap { Identity, MirrorY };  // MirrorY: (x, y) -> (x, -y), vy -> -vy

struct FieldDifference {
  double strain_rate = 0;  // ||e_A - e_B|| / ||e_A||, effective strain rate per element
  double velocity = 0;     // ||v_A - M v_B|| / ||v_A||, nodal velocity vectors
  int elements = 0, nodes = 0;
};

// Relative discrete L2 difference at the recorded step `step` (present in
// both files) over run A's elements and nodes whose initial position
// satisfies `select`. Throws when a selected point has no counterpart.
FieldDifference field_difference(const std::string& h5_a, const std::string& h5_b, int step,
                                 const std::function<bool(const Vec2&)>& select, PointMap map);

}  // namespace rpfem
