// Mesh generators (rectangle, ring, disk O-grid), sides, append, quality.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/generate.hpp"
#include "mesh/quality.hpp"

using namespace rpfem;

namespace {

double area(const Mesh& m) {
  double a = 0;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) {
      const Vec2 p = m.x[q[k]], r = m.x[q[(k + 1) % 4]];
      a += 0.5 * (p(0) * r(1) - r(0) * p(1));
    }
  return a;
}

// Signed area enclosed by the boundary edges (counter-clockwise: positive).
double boundary_area(const Mesh& m, const std::string& side) {
  double a = 0;
  for (const Edge& e : m.sides.at(side)) {
    const Vec2 p = m.x[e.a], r = m.x[e.b];
    a += 0.5 * (p(0) * r(1) - r(0) * p(1));
  }
  return a;
}

}  // namespace

TEST(Mesh, RectangleCountsSidesAndArea) {
  RectangleSpec s;
  s.x0 = 1;
  s.y0 = -2;
  s.width = 3;
  s.height = 2;
  s.nx = 6;
  s.ny = 4;
  const Mesh m = make_rectangle("b", s);
  EXPECT_EQ(m.num_elements(), 24);
  EXPECT_EQ(m.num_nodes(), 35);
  EXPECT_NEAR(area(m), 6.0, 1e-12);
  const auto top = m.side_nodes("b.top");
  EXPECT_EQ(top.size(), 7u);
  for (Index n : top) EXPECT_DOUBLE_EQ(m.x[n](1), 0.0);
  EXPECT_EQ(m.sides.at("b.boundary").size(), 20u);
  EXPECT_NEAR(boundary_area(m, "b.boundary"), 6.0, 1e-12);  // closed, counter-clockwise
  EXPECT_EQ(m.side_nodes("b.left").size(), 5u);
  EXPECT_NEAR(mesh_quality(m).min_scaled_jacobian, 1.0, 1e-12);
  EXPECT_NEAR(mesh_quality(m).max_aspect_ratio, 1.0, 1e-12);
  EXPECT_THROW(m.side_nodes("b.nowhere"), InputError);
}

TEST(Mesh, RingSides) {
  const Mesh m = make_ring("ring", {15, 30, 0, 10, 15, 10});
  EXPECT_EQ(m.num_elements(), 150);
  EXPECT_NEAR(area(m), 150.0, 1e-10);
  for (Index n : m.side_nodes("ring.inner")) EXPECT_DOUBLE_EQ(m.x[n](0), 15.0);
  for (Index n : m.side_nodes("ring.outer")) EXPECT_DOUBLE_EQ(m.x[n](0), 30.0);
}

class Disk : public ::testing::TestWithParam<int> {};

TEST_P(Disk, NoDegenerateElementsAndArcOnCircle) {
  const int n = GetParam();
  for (DiskPart part : {DiskPart::Half, DiskPart::UpperQuarter, DiskPart::LowerQuarter}) {
    DiskSpec s;
    s.radius = 10;
    s.center_y = 5;
    s.part = part;
    s.n = s.layers = n;
    const Mesh m = make_disk("s", s);
    const MeshQuality q = mesh_quality(m);
    EXPECT_GE(q.min_scaled_jacobian, 0.35) << "n = " << n;
    EXPECT_LT(q.max_aspect_ratio, 4.0);
    for (Index i : m.side_nodes("s.arc"))
      EXPECT_NEAR((m.x[i] - Vec2(0, 5)).norm(), 10.0, 1e-12 * 10);
    for (Index i : m.side_nodes("s.axis")) EXPECT_EQ(m.x[i](0), 0.0);
    for (const auto& p : m.x) EXPECT_GE(p(0), 0.0);
    const double exact = kPi * 100 / (part == DiskPart::Half ? 2 : 4);
    EXPECT_NEAR(area(m), exact, 0.05 * exact);
    EXPECT_NEAR(boundary_area(m, "s.boundary"), area(m), 1e-9 * exact);
    EXPECT_EQ(m.sides.count("s.plane"), part == DiskPart::Half ? 0u : 1u);
  }
}

INSTANTIATE_TEST_SUITE_P(Mesh, Disk, ::testing::Values(4, 8, 16));

TEST(Mesh, DiskAreaConvergesWithRefinement) {
  double prev = INFINITY;
  for (int n : {4, 8, 16, 32}) {
    DiskSpec s;
    s.radius = 1;
    s.n = s.layers = n;
    const double err = std::abs(area(make_disk("s", s)) - kPi / 2);
    EXPECT_LT(err, 0.3 * prev);  // polygonal arc: error ~ 1/n^2
    prev = err;
  }
}

TEST(Mesh, AppendShiftsIds) {
  Mesh a = make_rectangle("a", {0, 0, 1, 1, 2, 2});
  const Mesh b = make_rectangle("b", {0, 2, 1, 1, 1, 1});
  a.append(b);
  EXPECT_EQ(a.num_bodies(), 2);
  EXPECT_EQ(a.num_nodes(), 13);
  EXPECT_EQ(a.element_body.back(), 1);
  EXPECT_EQ(a.node_body.back(), 1);
  for (Index n : a.side_nodes("b.top")) EXPECT_DOUBLE_EQ(a.x[n](1), 3.0);
  for (const Edge& e : a.sides.at("b.boundary")) EXPECT_EQ(e.element, 4);
}

TEST(Mesh, InvertedElementHasNegativeQuality) {
  Mesh m = make_rectangle("b", {0, 0, 1, 1, 1, 1});
  std::vector<Vec2> x = m.x;
  std::swap(x[m.quads[0][1]], x[m.quads[0][3]]);  // clockwise
  EXPECT_LT(mesh_quality(m, x).min_scaled_jacobian, 0.0);
}
