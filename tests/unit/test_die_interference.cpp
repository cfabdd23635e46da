// A die's corners (geometry/die.hpp, corner_points) and how deep they
// reach into a body (model/die_interference.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/generate.hpp"
#include "model/die_interference.hpp"

using namespace rpfem;

TEST(DieCorners, SharpVerticesAndFilletPoints) {
  // A punch walked left to right: face, a 1 mm fillet, flank.
  const DieProfile sharp({{-1, 10}, {7, 10}, {7, 30}}, {0, 0, 0});
  const auto c = sharp.corner_points(Vec2(0, -2), false);
  ASSERT_EQ(c.size(), 1u);  // the one sharp vertex, shifted
  EXPECT_NEAR((c[0] - Vec2(7, 8)).norm(), 0, 1e-15);
  EXPECT_EQ(sharp.corner_points(Vec2::Zero(), true).size(), 3u);  // and the ends
  const DieProfile round({{-1, 10}, {7, 10}, {7, 30}}, {0, 1, 0});
  const auto f = round.corner_points(Vec2::Zero(), false);
  ASSERT_EQ(f.size(), 10u);  // 90 degrees every 10: ten points, ends included
  for (const Vec2& p : f) EXPECT_NEAR((p - Vec2(6, 11)).norm(), 1.0, 1e-12);
  EXPECT_NEAR((f.front() - Vec2(6, 10)).norm(), 0, 1e-12);
  EXPECT_NEAR((f.back() - Vec2(7, 11)).norm(), 0, 1e-12);
}

TEST(DieInterference, TheCornerDepthOverTheTargetSize) {
  // A 10 x 10 mm block (5 x 5 elements of 2 mm) and a punch whose sharp
  // corner at (4, 9.7) sits 0.3 mm inside the top edge from (4, 10) to (6, 10).
  Scene s;
  s.geometry = Geometry::PlaneStrain;
  s.mesh = make_rectangle("block", {0, 0, 10, 10, 5, 5});
  Die punch;
  punch.name = "punch";
  punch.profile = DieProfile({{-1, 9.7}, {4, 9.7}, {4, 30}}, {0, 0, 0});
  punch.motion = DieMotion(Vec2::Zero());
  s.dies.push_back(punch);
  ContactPair pair;
  pair.body = "block", pair.die = "punch", pair.body_id = 0, pair.die_id = 0;
  s.contact_pairs.push_back(pair);
  s.remesh.size = {2.0};
  s.remesh.die_corner_size = 0.5;
  const DieInterference d = die_interference(s, s.mesh.x, 0.0);
  EXPECT_NEAR(d.depth, 0.3, 1e-12);
  EXPECT_NEAR(d.relative, 0.3, 1e-12);  // over 2 mm x 0.5
  EXPECT_EQ(d.die, 0);
  EXPECT_EQ(d.body, 0);
  // Lifted 0.4 mm, the corner is outside: none.
  s.dies[0].motion = DieMotion(Vec2(0, 0.4));
  EXPECT_EQ(die_interference(s, s.mesh.x, 1.0).depth, 0.0);
}
