// Element quality, cheap enough to check every step: scaled Jacobian (the
// sine of the worst corner angle: 1 for a square, <= 0 for an inverted or
// degenerate element) and aspect ratio (longest over shortest edge).
#pragma once
#include <vector>

#include "mesh/mesh.hpp"

namespace rpfem {

struct MeshQuality {
  double min_scaled_jacobian = 1;
  double max_aspect_ratio = 1;
  Index worst_jacobian_element = -1;  // -1 for an empty mesh
  Index worst_aspect_element = -1;
  double min_area = 0;  // smallest signed element area (mm^2)
  // The least Jacobian determinant at the 2x2 Gauss points (mm^2 over the
  // parent square's area 4): <= 0 where an element is inverted at a point
  // the stiffness is integrated at.
  double min_gauss_jacobian = 0;
  Index worst_gauss_element = -1;
};

MeshQuality mesh_quality(const Mesh& mesh);
// The same on other node coordinates (the deformed configuration).
MeshQuality mesh_quality(const Mesh& mesh, const std::vector<Vec2>& x);

}  // namespace rpfem
