// Monitors: scalar geometric measures of the deformed bodies, declared in
// the case ([[monitors]]) and written as history.csv columns every step
// (e.g. a ring's inner diameter for friction calibration curves).
#pragma once
#include <string>
#include <vector>

#include "io/case_file.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

struct Monitor {
  enum class Quantity { MinX, MaxX, MinY, MaxY, XNear, YNear };
  enum class Change { None, Relative, Percent };
  std::string name;
  std::string side;  // "<body>.<side>"
  std::string quantity_name;
  Quantity quantity = Quantity::MinX;
  Change change = Change::None;
  Vec2 at = Vec2::Zero();  // XNear / YNear: initial point, mm
  std::vector<Index> nodes;  // the side's nodes (XNear / YNear: the one nearest `at`)
  double initial = 0;        // the raw value on the initial mesh
};

// Reads and validates [[monitors]] against the mesh. Throws InputError.
std::vector<Monitor> read_monitors(CaseSection root, const Mesh& mesh);
// After a remesh: each monitor's nodes on the new mesh, the side's nodes
// again, or (XNear / YNear) its node where the remesh kept it (kept: per
// old node, the new node at its place). The initial values stay.
void remap_monitors(std::vector<Monitor>& monitors, const Mesh& mesh, const std::vector<Index>& kept);
// Values at coordinates x: mm, or the change from the initial value.
std::vector<double> evaluate_monitors(const std::vector<Monitor>& monitors, const std::vector<Vec2>& x);

}  // namespace rpfem
