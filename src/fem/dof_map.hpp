// Nodal velocity constraints and the reduced unknowns they leave.
//
// A constraint v_node . n = g fixes one direction of a node's velocity
// (prescribed velocity component, symmetry plane, axis, a die's normal
// velocity in a rotated nodal frame as in ALPID). Elimination: each node's
// velocity is v = T u + p with T's columns an orthonormal basis of the
// unconstrained directions, u its reduced unknowns and p the prescribed part,
// so assembly works in any nodal frame (Kobayashi, Oh, Altan 1989, sec. 8.4).
#pragma once
#include <array>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

struct NodeConstraint {
  Index node = 0;
  Vec2 normal{1, 0};  // unit vector
  double value = 0;   // prescribed v . normal, mm/s
};

struct NodeFrame {
  int nfree = 2;                      // 0, 1 or 2
  std::array<Index, 2> dof{-1, -1};   // reduced dof of each free direction
  Eigen::Matrix2d T = Eigen::Matrix2d::Identity();  // columns: free directions
  Vec2 p = Vec2::Zero();              // prescribed part of the velocity
};

class DofMap {
 public:
  DofMap() = default;
  // Throws std::invalid_argument on conflicting constraints at a node.
  DofMap(Index num_nodes, const std::vector<NodeConstraint>& constraints);

  Index num_free() const { return nfree_; }
  Index num_nodes() const { return static_cast<Index>(frames_.size()); }
  const NodeFrame& frame(Index node) const { return frames_[node]; }
  // A number that changes whenever the reduced dof layout changes.
  std::uint64_t layout_hash() const { return hash_; }
  // Every node's frame the same to the bit: u maps to the same velocities.
  bool operator==(const DofMap& o) const;

  Vec2 velocity(Index node, const Vec& u) const;
  void expand(const Vec& u, std::vector<Vec2>& v) const;
  // Reduced coordinates of a nodal velocity field (least squares onto T).
  Vec reduce(const std::vector<Vec2>& v) const;

 private:
  std::vector<NodeFrame> frames_;
  Index nfree_ = 0;
  std::uint64_t hash_ = 0;
};

}  // namespace rpfem
