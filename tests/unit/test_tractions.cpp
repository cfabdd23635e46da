// Consistent nodal forces of surface tractions: the resultant of a uniform
// pressure equals pressure times area (2 pi r in axisymmetry), along the
// inward normal.
#include <gtest/gtest.h>

#include "mesh/generate.hpp"
#include "model/scene.hpp"
#include "model/step_problem.hpp"

using namespace rpfem;

TEST(Traction, PressureResultantAxisymmetric) {
  const Mesh m = make_ring("r", {2.0, 5.0, 0.0, 3.0, 7, 4});
  TractionLoad top;
  top.side = "r.top";
  top.pressure = 10.0;  // MPa
  const auto F = traction_forces(m, m.x, Geometry::Axisymmetric, {top});
  Vec2 sum = Vec2::Zero();
  for (const auto& f : F) sum += f;
  EXPECT_NEAR(sum(1), -10.0 * kPi * (25.0 - 4.0), 1e-9);  // pushes down on the top face
  EXPECT_NEAR(sum(0), 0.0, 1e-12);
  // Consistent, not lumped by length: sum_a F_a r_a = -p int N_a r_a 2 pi r ds
  // = -p 2 pi int r^2 dr (exact for the linear r), on every segment.
  double first = 0;
  for (Index i = 0; i < m.num_nodes(); ++i) first += F[i](1) * m.x[i](0);
  EXPECT_NEAR(first, -10.0 * 2 * kPi * (125.0 - 8.0) / 3.0, 1e-9);
}

TEST(Traction, VectorTractionPlaneStrain) {
  const Mesh m = make_rectangle("b", {0, 0, 4, 2, 4, 2});
  TractionLoad side;
  side.side = "b.right";
  side.t = Vec2(0.0, 3.0);  // shear traction, MPa
  const auto F = traction_forces(m, m.x, Geometry::PlaneStrain, {side});
  Vec2 sum = Vec2::Zero();
  for (const auto& f : F) sum += f;
  EXPECT_NEAR(sum(1), 3.0 * 2.0, 1e-12);  // per unit depth
  EXPECT_NEAR(sum(0), 0.0, 1e-12);
  for (Index n : m.side_nodes("b.left")) EXPECT_EQ(F[n].norm(), 0.0);
}
