// Rigid die profiles: signed distance and normal on segments, on fillet
// arcs (a node sliding around a rounded punch edge) and at sharp corners;
// die motion from a velocity table.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/die.hpp"

using namespace rpfem;

namespace {
// A punch: flat face at y = 5 from x = 0 to 10, then up the side x = 10.
DieProfile punch(double fillet) { return DieProfile({Vec2(0, 5), Vec2(10, 5), Vec2(10, 15)}, {0, fillet, 0}); }
}  // namespace

TEST(Die, FlatFaceSignedDistance) {
  const DieProfile d = punch(0);
  auto p = d.project(Vec2(3, 4));
  EXPECT_NEAR(p.distance, 1.0, 1e-14);
  EXPECT_NEAR((p.normal - Vec2(0, -1)).norm(), 0, 1e-14);
  EXPECT_FALSE(p.at_vertex);
  p = d.project(Vec2(3, 5.25));
  EXPECT_NEAR(p.distance, -0.25, 1e-14);  // inside the punch
  p = d.project(Vec2(3, 4), Vec2(0, -0.5));  // the die moved down by 0.5
  EXPECT_NEAR(p.distance, 0.5, 1e-14);
}

TEST(Die, NodeSlidingAroundFilletArc) {
  const DieProfile d = punch(2.0);
  ASSERT_EQ(d.pieces().size(), 3u);
  ASSERT_TRUE(d.pieces()[1].arc);
  EXPECT_NEAR((d.pieces()[1].center - Vec2(8, 7)).norm(), 0, 1e-12);
  // Around the edge at a gap of 0.1: the distance stays 0.1 and the normal
  // turns continuously from (0,-1) to (1,0), always the radial direction.
  Vec2 prev_n(0, -1);
  for (int k = 0; k <= 20; ++k) {
    const double th = -kPi / 2 + k * (kPi / 2) / 20;
    const Vec2 radial(std::cos(th), std::sin(th));
    const auto p = d.project(Vec2(8, 7) + 2.1 * radial);
    EXPECT_NEAR(p.distance, 0.1, 1e-12) << k;
    EXPECT_NEAR((p.normal - radial).norm(), 0, 1e-12) << k;
    EXPECT_NEAR((p.point - (Vec2(8, 7) + 2 * radial)).norm(), 0, 1e-12);
    EXPECT_LT((p.normal - prev_n).norm(), 0.1);
    prev_n = p.normal;
  }
  // Inside the rounded edge.
  const auto in = d.project(Vec2(8, 7) + 1.5 * Vec2(1, -1).normalized());
  EXPECT_NEAR(in.distance, -0.5, 1e-12);
}

TEST(Die, SharpNinetyDegreeCorner) {
  const DieProfile d = punch(0);
  // Diagonally outside the corner (10, 5): the corner is the closest point.
  auto p = d.project(Vec2(11, 4));
  EXPECT_TRUE(p.at_vertex);
  EXPECT_NEAR(p.distance, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR((p.normal - Vec2(1, -1).normalized()).norm(), 0, 1e-12);
  // Outside below the face near the corner, and beside the side.
  EXPECT_NEAR(d.project(Vec2(9.5, 4.9)).distance, 0.1, 1e-12);
  EXPECT_NEAR(d.project(Vec2(10.2, 6)).distance, 0.2, 1e-12);
  // Inside, near the corner.
  EXPECT_LT(d.project(Vec2(9.9, 5.1)).distance, 0);
}

TEST(Die, ConcaveCorner) {
  // A bottom die walked right to left: floor y = 0 from x = 10 to 2, then a
  // wall up x = 2... walked with the material on the left: (10,0)->(2,0)->(2,-5)
  // is a right turn into the material's side: the corner (2,0) is concave.
  const DieProfile d({Vec2(10, 0), Vec2(2, 0), Vec2(2, 5)}, {});
  // Walking (2,0) -> (2,5) the material is on the left (x < 2): a pocket
  // for the workpiece at x > 2, y > 0.
  EXPECT_NEAR(d.project(Vec2(3, 1)).distance, 1.0, 1e-12);
  EXPECT_LT(d.project(Vec2(1.5, 0.5)).distance, 0);  // in the wall
  EXPECT_LT(d.project(Vec2(3, -0.5)).distance, 0);   // in the floor
}

TEST(Die, FilletTooLargeIsRejected) {
  EXPECT_THROW(DieProfile({Vec2(0, 0), Vec2(1, 0), Vec2(1, 1)}, {0, 5.0, 0}), std::invalid_argument);
}

TEST(Die, MotionFromTable) {
  const DieMotion m(std::vector<std::array<double, 3>>{{0.0, 0.0, -1.0}, {2.0, 0.0, -3.0}, {4.0, 0.0, -3.0}});
  EXPECT_NEAR(m.velocity(1.0)(1), -2.0, 1e-14);
  EXPECT_NEAR(m.displacement(2.0)(1), -4.0, 1e-14);   // trapezoid, exact
  EXPECT_NEAR(m.displacement(5.0)(1), -13.0, 1e-14);  // held constant past the end
  EXPECT_NEAR(DieMotion(Vec2(0, -0.5)).displacement(4.0)(1), -2.0, 1e-14);
  EXPECT_NEAR(m.max_speed(), 3.0, 1e-14);
}

TEST(Die, PolylineDrawsArcsToTheSagitta) {
  // The punch with a 2 mm fillet, shifted: the face's start, the arc's
  // chords, the flank's end; no chord strays from the arc by more than the
  // sagitta.
  const DieProfile d = punch(2.0);
  const Vec2 shift(0, -1);
  const double sagitta = 1e-3;
  const auto p = d.polyline(shift, sagitta);
  EXPECT_NEAR((p.front() - Vec2(0, 4)).norm(), 0, 1e-14);
  EXPECT_NEAR((p.back() - Vec2(10, 14)).norm(), 0, 1e-14);
  // A quarter turn of radius 2 in chords of sagitta 1e-3: at least
  // (pi / 2) / (2 acos(1 - 5e-4)) = 24.8 of them.
  EXPECT_GE(p.size(), 2u + 25u);
  const Vec2 center(8, 6);  // the fillet's centre, shifted
  for (std::size_t i = 1; i + 1 < p.size(); ++i) {
    EXPECT_NEAR((p[i] - center).norm(), 2.0, 1e-12);
    if (i + 2 < p.size()) EXPECT_LE(2.0 - (0.5 * (p[i] + p[i + 1]) - center).norm(), sagitta * (1 + 1e-9));
  }
  EXPECT_EQ(punch(0).polyline(Vec2::Zero(), sagitta).size(), 3u);  // sharp: the vertices
}
