#include "model/boundary.hpp"

#include <algorithm>
#include <cmath>

namespace rpfem {

Vec2 symmetry_load_factor(const std::vector<SymmetryPlane>& planes, const std::vector<Vec2>& x,
                          const std::vector<Index>& nodes, double tol) {
  Vec2 f(1, 1);
  for (const auto& p : planes)
    if (std::any_of(nodes.begin(), nodes.end(), [&](Index n) { return std::abs(x[n](p.axis) - p.at) <= tol; })) {
      f *= 2;
      f(p.axis) = 0;
    }
  return f;
}

KernelConstraints::KernelConstraints(const Scene& scene) : symmetry_(scene.symmetry) {
  const Mesh& m = scene.mesh;
  size = m.size();
  tol_ = 1e-9 * size;
  for (const auto& g : scene.velocities) {
    Group grp{g.name, m.side_nodes(g.side), 0.0};
    const Vec2 v(g.vx.value_or(0), g.vy.value_or(0));
    grp.speed = v.norm();
    for (Index n : grp.nodes) {
      if (g.vx) constraints.push_back({n, Vec2(1, 0), *g.vx});
      if (g.vy) constraints.push_back({n, Vec2(0, 1), *g.vy});
    }
    groups_.push_back(std::move(grp));
  }
  for (const auto& p : scene.symmetry) {
    volume_factor *= 2;
    const Vec2 n = p.axis == 0 ? Vec2(1, 0) : Vec2(0, 1);
    for (Index i = 0; i < m.num_nodes(); ++i)
      if (std::abs(m.x[i](p.axis) - p.at) <= tol_) constraints.push_back({i, n, 0.0});
  }
  if (scene.geometry == Geometry::Axisymmetric)
    for (Index i = 0; i < m.num_nodes(); ++i)
      if (std::abs(m.x[i](0)) <= tol_) constraints.push_back({i, Vec2(1, 0), 0.0});
}

std::optional<double> KernelConstraints::group_speed(const std::string& name) const {
  for (const auto& g : groups_)
    if (g.name == name) return g.speed;
  return std::nullopt;
}

std::vector<std::string> KernelConstraints::load_names() const {
  std::vector<std::string> n;
  for (const auto& g : groups_) n.push_back(g.name);
  return n;
}

std::vector<Vec2> KernelConstraints::group_loads(const std::vector<Vec2>& x, const std::vector<Vec2>& F) const {
  std::vector<Vec2> loads;
  for (const auto& g : groups_) {
    Vec2 sum = Vec2::Zero();
    for (Index n : g.nodes) sum += F[n];
    loads.push_back(sum.cwiseProduct(symmetry_load_factor(symmetry_, x, g.nodes, tol_)));
  }
  return loads;
}

}  // namespace rpfem
