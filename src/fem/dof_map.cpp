#include "fem/dof_map.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rpfem {

DofMap::DofMap(Index num_nodes, const std::vector<NodeConstraint>& constraints)
    : frames_(static_cast<std::size_t>(num_nodes)) {
  // Gather up to two independent constraints per node.
  std::vector<std::vector<const NodeConstraint*>> per_node(frames_.size());
  for (const auto& c : constraints) {
    if (c.node < 0 || c.node >= num_nodes) throw std::invalid_argument("constraint on a node out of range");
    auto& list = per_node[c.node];
    bool redundant = false;
    for (const auto* o : list) {
      const double cross = o->normal(0) * c.normal(1) - o->normal(1) * c.normal(0);
      if (std::abs(cross) < 1e-9) {
        // Parallel: must agree, then it adds nothing.
        const double s = o->normal.dot(c.normal);
        if (std::abs(s * o->value - c.value) > 1e-9 * (1 + std::abs(c.value)))
          throw std::invalid_argument("conflicting velocity constraints at node " + std::to_string(c.node));
        redundant = true;
      }
    }
    if (redundant) continue;
    if (list.size() == 2)
      throw std::invalid_argument("more than two velocity constraints at node " + std::to_string(c.node));
    list.push_back(&c);
  }
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t x) { h = (h ^ x) * 1099511628211ull; };
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    NodeFrame& f = frames_[i];
    const auto& list = per_node[i];
    if (list.size() == 1) {
      const Vec2 n = list[0]->normal.normalized();
      f.nfree = 1;
      f.T.setZero();
      f.T.col(0) = Vec2(-n(1), n(0));
      f.p = list[0]->value / list[0]->normal.norm() * n;
    } else if (list.size() == 2) {
      Eigen::Matrix2d A;
      A.row(0) = list[0]->normal.transpose();
      A.row(1) = list[1]->normal.transpose();
      f.nfree = 0;
      f.T.setZero();
      f.p = A.inverse() * Vec2(list[0]->value, list[1]->value);
    }
    for (int k = 0; k < f.nfree; ++k) f.dof[k] = nfree_++;
    mix(static_cast<std::uint64_t>(f.nfree));
  }
  hash_ = h ^ static_cast<std::uint64_t>(nfree_);
}

Vec2 DofMap::velocity(Index node, const Vec& u) const {
  const NodeFrame& f = frames_[node];
  Vec2 v = f.p;
  for (int k = 0; k < f.nfree; ++k) v += f.T.col(k) * u(f.dof[k]);
  return v;
}

void DofMap::expand(const Vec& u, std::vector<Vec2>& v) const {
  v.resize(frames_.size());
  for (std::size_t i = 0; i < frames_.size(); ++i) v[i] = velocity(static_cast<Index>(i), u);
}

Vec DofMap::reduce(const std::vector<Vec2>& v) const {
  Vec u(nfree_);
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const NodeFrame& f = frames_[i];
    for (int k = 0; k < f.nfree; ++k) u(f.dof[k]) = f.T.col(k).dot(v[i] - f.p);
  }
  return u;
}

bool DofMap::operator==(const DofMap& o) const {
  if (hash_ != o.hash_ || frames_.size() != o.frames_.size()) return false;
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const NodeFrame &a = frames_[i], &b = o.frames_[i];
    if (a.nfree != b.nfree || a.dof != b.dof || a.T != b.T || a.p != b.p) return false;
  }
  return true;
}

}  // namespace rpfem
