// The outline mesher (mesh/outline_mesher.hpp, gmsh): on a deformed body
// it keeps every boundary node where it was, bounds exactly the old area
// and axisymmetric volume, rebuilds each named side along the same edges,
// and gives counter-clockwise quadrilaterals of about the target size.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mesh/generate.hpp"
#include "mesh/outline_mesher.hpp"
#include "mesh/quality.hpp"

using namespace rpfem;

namespace {

// Area and int r dA of a polygon a -> b over its edges (counter-clockwise:
// positive; Green's theorem, exact for straight edges).
struct Moments {
  double area = 0, r = 0;
  void add(const Vec2& a, const Vec2& b) {
    const double c = cross(a, b);
    area += 0.5 * c;
    r += (a(0) + b(0)) * c / 6;
  }
};

Moments of_elements(const Mesh& m) {
  Moments s;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) s.add(m.x[q[k]], m.x[q[(k + 1) % 4]]);
  return s;
}

Moments of_side(const Mesh& m, const std::vector<Vec2>& x, const std::string& side) {
  Moments s;
  for (const Edge& e : m.sides.at(side)) s.add(x[e.a], x[e.b]);
  return s;
}

}  // namespace

TEST(OutlineMesher, KeepsTheOutlineItsNodesAndSides) {
  // A 10 x 5 mm billet (10 x 5 elements) barrelled: its right side bulges
  // by up to 1 mm, its top sinks by up to 0.3 mm toward the axis.
  const Mesh old = make_rectangle("billet", {0, 0, 10, 5, 10, 5});
  std::vector<Vec2> x = old.x;
  for (Vec2& p : x) {
    p(0) *= 1 + 0.1 * std::sin(kPi * p(1) / 5);
    p(1) -= 0.3 * (p(1) / 5) * (1 - p(0) / 12);
  }
  const double size = 0.6;
  const OutlineMesh out = mesh_outline(old, x, 0, {size});
  const Mesh& m = out.mesh;
  ASSERT_EQ(m.body_names, std::vector<std::string>{"billet"});

  // Every old boundary node is a new node at the same place, to the bit.
  int kept = 0;
  for (const Edge& e : old.sides.at("billet.boundary")) {
    ASSERT_GE(out.kept[e.a], 0) << "old node " << e.a;
    EXPECT_EQ(m.x[out.kept[e.a]], x[e.a]);
    ++kept;
  }
  EXPECT_EQ(kept, 30);

  // The elements fill the old outline exactly: area and int r dA (the
  // volume over 2 pi).
  const Moments before = of_side(old, x, "billet.boundary"), after = of_elements(m);
  EXPECT_NEAR(after.area, before.area, 1e-12 * before.area);
  EXPECT_NEAR(after.r, before.r, 1e-12 * before.r);
  EXPECT_NEAR(of_side(m, m.x, "billet.boundary").area, before.area, 1e-12 * before.area);

  // Each side again: a chain of edges from its old first node to its old
  // last node, each edge an edge of its element.
  for (const std::string side : {"bottom", "right", "top", "left", "boundary"}) {
    const auto& o = old.sides.at("billet." + side);
    const auto& n = m.sides.at("billet." + side);
    ASSERT_GE(n.size(), o.size()) << side;
    EXPECT_EQ(n.front().a, out.kept[o.front().a]) << side;
    for (std::size_t k = 0; k + 1 < n.size(); ++k) EXPECT_EQ(n[k].b, n[k + 1].a) << side << " edge " << k;
    if (side != "boundary") EXPECT_EQ(n.back().b, out.kept[o.back().b]) << side;
    for (const Edge& e : n) {
      const auto& q = m.quads.at(e.element);
      bool found = false;
      for (int i = 0; i < 4; ++i) found = found || (q[i] == e.a && q[(i + 1) % 4] == e.b);
      EXPECT_TRUE(found) << side << " edge " << e.a << "-" << e.b;
    }
  }

  // Counter-clockwise quadrilaterals of about the target size, none poor.
  const MeshQuality q = mesh_quality(m);
  EXPECT_GT(q.min_area, 0);
  EXPECT_GT(q.min_scaled_jacobian, 0.3);
  double edges = 0;
  for (const auto& quad : m.quads)
    for (int k = 0; k < 4; ++k) edges += (m.x[quad[(k + 1) % 4]] - m.x[quad[k]]).norm();
  const double mean = edges / (4.0 * m.num_elements());
  EXPECT_GT(mean, 0.6 * size);
  EXPECT_LT(mean, 1.4 * size);
  std::printf("[measured] outline mesher: %lld quads, mean edge %.3f mm (target %.2f), least scaled Jacobian %.3f, "
              "area %.2e and volume %.2e off the outline's\n",
              static_cast<long long>(m.num_elements()), mean, size, q.min_scaled_jacobian,
              std::abs(after.area / before.area - 1), std::abs(after.r / before.r - 1));
}

TEST(OutlineMesher, DropsNodesInLineButKeepsSideEndsAndPinnedNodes) {
  // A 10 x 5 mm billet meshed 40 x 20 (0.25 mm edges), remeshed at 1 mm:
  // the nodes in line on each straight side go, the corners (the sides'
  // ends) and a pinned node in the middle of the right side stay, and the
  // area is the old one exactly (only nodes exactly in line go at
  // volume_tolerance 0).
  const Mesh old = make_rectangle("billet", {0, 0, 10, 5, 40, 20});
  Index pinned = -1;
  for (Index n = 0; n < old.num_nodes(); ++n)
    if ((old.x[n] - Vec2(10, 2.5)).norm() < 1e-12) pinned = n;
  ASSERT_GE(pinned, 0);
  OutlineOptions o;
  o.size = 1.0;
  o.pinned = {pinned};
  const OutlineMesh out = mesh_outline(old, old.x, 0, o);
  const Mesh& m = out.mesh;
  int kept = 0;
  for (const Edge& e : old.sides.at("billet.boundary")) kept += out.kept[e.a] >= 0;
  EXPECT_LT(kept, 40);  // of 120 outline nodes
  for (const Vec2 c : {Vec2(0, 0), Vec2(10, 0), Vec2(10, 5), Vec2(0, 5), Vec2(10, 2.5)}) {
    Index n = -1;
    for (Index i = 0; i < old.num_nodes(); ++i)
      if ((old.x[i] - c).norm() < 1e-12) n = i;
    ASSERT_GE(out.kept[n], 0) << c.transpose();
    EXPECT_EQ(m.x[out.kept[n]], c) << c.transpose();
  }
  // Each side from its old first node to its old last, edges of about the size.
  for (const std::string side : {"bottom", "right", "top", "left"}) {
    const auto& o_edges = old.sides.at("billet." + side);
    const auto& n_edges = m.sides.at("billet." + side);
    EXPECT_EQ(n_edges.front().a, out.kept[o_edges.front().a]) << side;
    EXPECT_EQ(n_edges.back().b, out.kept[o_edges.back().b]) << side;
    for (const Edge& e : n_edges) EXPECT_LT((m.x[e.b] - m.x[e.a]).norm(), 1.0 + 1e-9) << side;
  }
  const Moments before = of_side(old, old.x, "billet.boundary"), after = of_elements(m);
  EXPECT_NEAR(after.area, 50.0, 1e-12);
  EXPECT_NEAR(after.r, before.r, 1e-12 * before.r);
  std::printf("[measured] outline mesher on a 40 x 20 billet at 1 mm: %d of 120 outline nodes kept, %lld quads\n",
              kept, static_cast<long long>(m.num_elements()));
}
