// Mesh generators (rectangle, ring, disk O-grid), sides, append, quality.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "mesh/generate.hpp"
#include "mesh/quality.hpp"

using namespace rpfem;

namespace {

double cross(const Vec2& a, const Vec2& b) { return a(0) * b(1) - a(1) * b(0); }

double area(const Mesh& m) {
  double a = 0;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) a += 0.5 * cross(m.x[q[k]], m.x[q[(k + 1) % 4]]);
  return a;
}

// Signed area enclosed by the edges of a side (counter-clockwise: positive).
double boundary_area(const Mesh& m, const std::string& side) {
  double a = 0;
  for (const Edge& e : m.sides.at(side)) a += 0.5 * cross(m.x[e.a], m.x[e.b]);
  return a;
}

// The structural checks every generated mesh must pass: ids in range, the
// boundary a single closed loop whose edges are element edges in the
// element's own (counter-clockwise) direction, no duplicate nodes (Euler's
// formula for a disk-like region: V - E + F = 1), every named side a run of
// the boundary.
void check_structure(const Mesh& m, const std::string& body) {
  ASSERT_EQ(m.element_body.size(), m.quads.size());
  ASSERT_EQ(m.node_body.size(), m.x.size());
  ASSERT_EQ(m.body_names, std::vector<std::string>{body});
  const auto& bnd = m.sides.at(body + ".boundary");
  std::map<Index, Index> next;
  std::set<std::pair<Index, Index>> bset;
  for (const Edge& e : bnd) {
    ASSERT_TRUE(next.emplace(e.a, e.b).second) << "node " << e.a << " starts two boundary edges";
    bset.insert({e.a, e.b});
    const auto& q = m.quads.at(e.element);
    bool found = false;
    for (int k = 0; k < 4; ++k) found |= q[k] == e.a && q[(k + 1) % 4] == e.b;
    EXPECT_TRUE(found) << "edge " << e.a << "->" << e.b << " not a ccw edge of its element";
  }
  // Walk the loop from the first edge: it must come back after all edges.
  Index n = bnd.front().a, steps = 0;
  do {
    ASSERT_TRUE(next.count(n));
    n = next[n];
    ++steps;
  } while (n != bnd.front().a && steps <= Index(bnd.size()));
  EXPECT_EQ(steps, Index(bnd.size()));
  // Each interior edge is shared by two elements; each boundary edge by one.
  const Index edges = (4 * m.num_elements() + Index(bnd.size())) / 2;
  EXPECT_EQ(m.num_nodes() - edges + m.num_elements(), 1);
  for (const auto& [name, side] : m.sides) {
    for (const Edge& e : side) EXPECT_TRUE(bset.count({e.a, e.b})) << name;
    // Sides come as one counter-clockwise run (all generated shapes have
    // connected sides).
    for (std::size_t k = 0; k + 1 < side.size(); ++k) EXPECT_EQ(side[k].b, side[k + 1].a) << name;
  }
  EXPECT_NEAR(boundary_area(m, body + ".boundary"), area(m), 1e-12 * std::abs(area(m)));
  EXPECT_GT(mesh_quality(m).min_scaled_jacobian, 0.0);
}

}  // namespace

TEST(Mesh, Rectangle) {
  RectangleSpec s;
  s.x0 = 1;
  s.y0 = -2;
  s.width = 3;
  s.height = 2;
  s.nx = 6;
  s.ny = 4;
  const Mesh m = make_rectangle("b", s);
  check_structure(m, "b");
  EXPECT_EQ(m.num_elements(), 24);
  EXPECT_EQ(m.num_nodes(), 35);
  EXPECT_NEAR(area(m), 6.0, 1e-12);
  const auto top = m.side_nodes("b.top");
  EXPECT_EQ(top.size(), 7u);
  for (Index n : top) EXPECT_EQ(m.x[n](1), 0.0);
  for (Index n : m.side_nodes("b.right")) EXPECT_EQ(m.x[n](0), 4.0);
  EXPECT_EQ(m.side_nodes("b.left").size(), 5u);
  EXPECT_EQ(m.side_nodes("b.bottom").size(), 7u);
  EXPECT_EQ(m.sides.at("b.boundary").size(), 20u);
  EXPECT_EQ(m.sides.size(), 5u);
  const MeshQuality q = mesh_quality(m);
  EXPECT_NEAR(q.min_scaled_jacobian, 1.0, 1e-12);
  EXPECT_NEAR(q.max_aspect_ratio, 1.0, 1e-12);
  EXPECT_NEAR(q.min_area, 0.25, 1e-12);
}

TEST(Mesh, UnknownSideThrows) {
  const Mesh m = make_rectangle("b", {});
  EXPECT_THROW(m.side_nodes("b.nowhere"), InputError);
  try {
    m.side_nodes("nowhere");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.top"), std::string::npos) << e.what();
  }
}

TEST(Mesh, Ring) {
  const Mesh m = make_ring("ring", {15, 30, 5, 10, 15, 10});
  check_structure(m, "ring");
  EXPECT_EQ(m.num_elements(), 150);
  EXPECT_EQ(m.num_nodes(), 16 * 11);
  EXPECT_NEAR(area(m), 150.0, 1e-10);
  EXPECT_EQ(m.sides.at("ring.boundary").size(), 50u);
  EXPECT_EQ(m.side_nodes("ring.inner").size(), 11u);
  for (Index n : m.side_nodes("ring.inner")) EXPECT_EQ(m.x[n](0), 15.0);
  for (Index n : m.side_nodes("ring.outer")) EXPECT_EQ(m.x[n](0), 30.0);
  for (Index n : m.side_nodes("ring.bottom")) EXPECT_EQ(m.x[n](1), 5.0);
  for (Index n : m.side_nodes("ring.top")) EXPECT_EQ(m.x[n](1), 15.0);
}

class Disk : public ::testing::TestWithParam<int> {};

TEST_P(Disk, NoDegenerateElementsArcOnCircleSides) {
  const int n = GetParam();
  for (DiskPart part : {DiskPart::Half, DiskPart::UpperQuarter, DiskPart::LowerQuarter}) {
    const bool half = part == DiskPart::Half;
    DiskSpec s;
    s.radius = 10;
    s.center_y = 5;
    s.part = part;
    s.n = s.layers = n;
    const Mesh m = make_disk("s", s);
    check_structure(m, "s");
    const MeshQuality q = mesh_quality(m);
    EXPECT_GE(q.min_scaled_jacobian, 0.35) << "n = " << n;
    EXPECT_LT(q.max_aspect_ratio, 3.0) << "n = " << n;
    // Quarter: inner n x n block, two layers x n outer blocks.
    const int quarter = n * n + 2 * n * n;
    EXPECT_EQ(m.num_elements(), half ? 2 * quarter : quarter);
    // Boundary: arc 2n (per quarter), axis n + layers, plane n + layers.
    const auto arc = m.side_nodes("s.arc");
    EXPECT_EQ(m.sides.at("s.boundary").size(), half ? 8u * n : 6u * n);
    EXPECT_EQ(arc.size(), (half ? 4u : 2u) * n + 1);
    for (Index i : arc) EXPECT_NEAR((m.x[i] - Vec2(0, 5)).norm(), 10.0, 1e-12 * 10);
    EXPECT_EQ(m.side_nodes("s.axis").size(), (half ? 4u : 2u) * n + 1);
    for (Index i : m.side_nodes("s.axis")) EXPECT_EQ(m.x[i](0), 0.0);
    for (const auto& p : m.x) {
      EXPECT_GE(p(0), 0.0);
      EXPECT_LE(p(1), part == DiskPart::LowerQuarter ? 5.0 : 15.0);
      EXPECT_GE(p(1), part == DiskPart::UpperQuarter ? 5.0 : -5.0);
    }
    EXPECT_EQ(m.sides.count("s.plane"), half ? 0u : 1u);
    if (!half) {
      EXPECT_EQ(m.side_nodes("s.plane").size(), 2u * n + 1);
      for (Index i : m.side_nodes("s.plane")) EXPECT_EQ(m.x[i](1), 5.0);
    }
    // The mesh fills the inscribed polygon of the arc (chords of pi/4n).
    const double exact = kPi * 100 / (half ? 2 : 4), phi = kPi / (4 * n);
    EXPECT_NEAR(area(m), exact * std::sin(phi) / phi, 1e-12 * exact);
    std::printf("[ disk n = layers = %2d %-12s] min scaled Jacobian %.4f, max aspect ratio %.3f\n", n,
                half ? "half" : part == DiskPart::UpperQuarter ? "upper" : "lower", q.min_scaled_jacobian,
                q.max_aspect_ratio);
  }
}

INSTANTIATE_TEST_SUITE_P(Mesh, Disk, ::testing::Values(1, 2, 4, 8, 16));

TEST(Mesh, DiskAreaConvergesWithRefinement) {
  for (DiskPart part : {DiskPart::Half, DiskPart::UpperQuarter}) {
    const double exact = kPi / (part == DiskPart::Half ? 2 : 4);
    double prev = INFINITY;
    for (int n : {4, 8, 16, 32}) {
      DiskSpec s;
      s.radius = 1;
      s.part = part;
      s.n = s.layers = n;
      const double err = std::abs(area(make_disk("s", s)) - exact);
      EXPECT_LT(err, 0.3 * prev);  // inscribed polygon: error ~ 1/n^2
      prev = err;
    }
    EXPECT_LT(prev, 1e-3 * exact);
  }
}

TEST(Mesh, DiskUnequalDivisions) {
  DiskSpec s;
  s.radius = 3;
  s.n = 3;
  s.layers = 7;
  const Mesh m = make_disk("s", s);
  check_structure(m, "s");
  EXPECT_EQ(m.num_elements(), 2 * (9 + 2 * 21));
}

TEST(Mesh, AppendShiftsIds) {
  Mesh a = make_rectangle("a", {0, 0, 1, 1, 2, 2});
  const Mesh b = make_rectangle("b", {0, 2, 1, 1, 1, 1});
  a.append(b);
  EXPECT_EQ(a.num_bodies(), 2);
  EXPECT_EQ(a.body_names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(a.num_nodes(), 13);
  EXPECT_EQ(a.num_elements(), 5);
  EXPECT_EQ(a.quads.back(), (std::array<Index, 4>{9, 10, 12, 11}));
  EXPECT_EQ(std::count(a.element_body.begin(), a.element_body.end(), 1), 1);
  EXPECT_EQ(std::count(a.node_body.begin(), a.node_body.end(), 1), 4);
  EXPECT_EQ(a.node_body[8], 0);
  EXPECT_EQ(a.node_body[9], 1);
  EXPECT_EQ(a.side_nodes("b.top"), (std::vector<Index>{11, 12}));
  for (Index n : a.side_nodes("b.top")) EXPECT_EQ(a.x[n](1), 3.0);
  EXPECT_EQ(a.side_nodes("a.top"), (std::vector<Index>{6, 7, 8}));
  for (const Edge& e : a.sides.at("b.boundary")) {
    EXPECT_EQ(e.element, 4);
    EXPECT_GE(e.a, 9);
    EXPECT_GE(e.b, 9);
  }
  EXPECT_EQ(a.sides.size(), 10u);
  EXPECT_THROW(a.append(b), InputError);  // same body twice
}

TEST(Mesh, InvertedElementHasNegativeQuality) {
  const Mesh m = make_rectangle("b", {0, 0, 1, 1, 1, 1});
  std::vector<Vec2> x = m.x;
  std::swap(x[m.quads[0][1]], x[m.quads[0][3]]);  // clockwise
  const MeshQuality q = mesh_quality(m, x);
  EXPECT_NEAR(q.min_scaled_jacobian, -1.0, 1e-12);
  EXPECT_EQ(q.worst_jacobian_element, 0);
  EXPECT_LT(q.min_area, 0.0);
  EXPECT_NEAR(q.min_gauss_jacobian, -0.25, 1e-12);
  // A non-convex (arrow-head) element: one corner beyond 180 degrees.
  x = m.x;
  x[m.quads[0][2]] = Vec2(0.2, 0.2);
  EXPECT_LT(mesh_quality(m, x).min_scaled_jacobian, 0.0);
  EXPECT_GT(mesh_quality(m, x).min_area, 0.0);
  // ... and inverted at the Gauss point next to it.
  EXPECT_LT(mesh_quality(m, x).min_gauss_jacobian, 0.0);
  EXPECT_EQ(mesh_quality(m, x).worst_gauss_element, 0);
  // A corner just beyond 180 degrees (node 2 just inside the diagonal from
  // node 1 to node 3): a reflex corner, the Gauss points still positive.
  x = m.x;
  x[m.quads[0][2]] = Vec2(0.49, 0.49);
  EXPECT_LT(mesh_quality(m, x).min_scaled_jacobian, 0.0);
  EXPECT_GT(mesh_quality(m, x).min_gauss_jacobian, 0.0);
  // The unit square: det J = 1/4 (its area over the parent square's 4).
  EXPECT_NEAR(mesh_quality(m).min_gauss_jacobian, 0.25, 1e-15);
  // A stretched element: aspect ratio 4, still a rectangle.
  x = m.x;
  for (auto& p : x) p(0) *= 4;
  EXPECT_NEAR(mesh_quality(m, x).max_aspect_ratio, 4.0, 1e-12);
  EXPECT_NEAR(mesh_quality(m, x).min_scaled_jacobian, 1.0, 1e-12);
}
