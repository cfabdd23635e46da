// The kernel's own velocity constraints of a scene: prescribed velocities on
// sides (platens), symmetry planes (v.n = 0) and, in axisymmetry, the axis
// (v_r = 0 at r = 0). Also the whole-body bookkeeping of half models.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "fem/dof_map.hpp"
#include "model/scene.hpp"

namespace rpfem {

class KernelConstraints {
 public:
  KernelConstraints() = default;
  explicit KernelConstraints(const Scene& scene);

  std::vector<NodeConstraint> constraints;
  double volume_factor = 1;  // 2 per symmetry plane
  double size = 0;           // largest bounding-box side of the modelled bodies, mm

  std::optional<double> group_speed(const std::string& name) const;
  std::vector<std::string> load_names() const;  // one per velocity group
  // Whole-body load on each velocity group: the sum of the nodal forces of
  // its nodes, mirrored across each symmetry plane that the group touches
  // (the mirror image is part of the same platen): symmetry_load_factor.
  std::vector<Vec2> group_loads(const std::vector<Vec2>& x, const std::vector<Vec2>& F) const;

 private:
  struct Group {
    std::string name;
    std::vector<Index> nodes;
    double speed = 0;
  };
  std::vector<Group> groups_;
  std::vector<SymmetryPlane> symmetry_;
  double tol_ = 0;
};

// Whole-model load from a half or quarter model's: for each symmetry plane
// on which at least one of the nodes lies, the mirrored half doubles the
// component along the plane and cancels the component normal to it. Apply
// with load.cwiseProduct(factor).
Vec2 symmetry_load_factor(const std::vector<SymmetryPlane>& planes, const std::vector<Vec2>& x,
                            const std::vector<Index>& nodes, double tol);

}  // namespace rpfem
