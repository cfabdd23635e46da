// Node-to-segment search (contact/segment_search.hpp) on crafted master
// surfaces: a node on a segment, exactly on a segment end, past a convex
// corner, over a sliver segment, penetrated; the bucket grid against all
// pairs; the least-squares line of paper Fig. 3.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/segment_search.hpp"

using namespace rpfem;

namespace {

// A master surface along the given points (body below/left: walked so the
// body is on the left, i.e. right to left for a body below a horizontal line).
struct Surface {
  std::vector<Vec2> x;
  ContactSurface s;
  explicit Surface(std::vector<Vec2> pts) : x(std::move(pts)) {
    for (Index i = 0; i + 1 < static_cast<Index>(x.size()); ++i) {
      s.edges.push_back({i, i + 1, 0});
      s.nodes.push_back(i);
    }
    s.nodes.push_back(static_cast<Index>(x.size()) - 1);
  }
  std::optional<SegmentHit> find(const Vec2& p, double capture = 0.5, Vec2 slave_n = Vec2::Zero()) {
    SegmentGrid grid(x, s, capture);
    return find_segment(x, s, grid, p, capture, slave_n);
  }
};

}  // namespace

TEST(SegmentSearch, NodeOverASegmentGetsSignedGapAndPosition) {
  // Flat master top at y = 0, walked right to left: outward normal +y.
  Surface m({{3, 0}, {2, 0}, {1, 0}, {0, 0}});
  auto h = m.find({1.25, 0.1});
  ASSERT_TRUE(h);
  EXPECT_EQ(h->edge, 1);  // segment (2,0)-(1,0)
  EXPECT_NEAR(h->gap, 0.1, 1e-14);
  // Normal and position from the least-squares line through the slave
  // node and the segment's ends (paper Fig. 3): tilted slightly toward S.
  const LeastSquaresLine ls = least_squares_line({1.25, 0.1}, {2, 0}, {1, 0});
  EXPECT_NEAR(h->xi, ls.xi, 1e-14);
  EXPECT_NEAR((h->normal - ls.normal).norm(), 0.0, 1e-14);
  EXPECT_NEAR(h->xi, 0.75, 0.01);
  EXPECT_NEAR(h->normal(1), 1.0, 1e-3);
  auto in = m.find({1.25, -0.05});  // penetrated: the signed area changes sign
  ASSERT_TRUE(in);
  EXPECT_NEAR(in->gap, -0.05, 1e-14);
  EXPECT_FALSE(m.find({1.25, 0.6}));  // beyond the capture distance
}

TEST(SegmentSearch, NodeExactlyOnASegmentEndTakesTheSegmentFacingIt) {
  // A kinked master: flat from x = 0 to 1, then sloping down to x = 2 (the
  // edge of a contact zone). A slave node exactly on the kink vertex.
  Surface m({{2, -0.2}, {1, 0}, {0, 0}});
  // The slave surface's normal points down (the slave body is above).
  auto h = m.find({1, 0}, 0.5, Vec2(0, -1));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->edge, 1);  // the flat segment, whose normal opposes the slave's
  EXPECT_NEAR(h->gap, 0.0, 1e-15);
  EXPECT_NEAR(h->xi, 0.0, 1e-12);
  EXPECT_NEAR(h->normal(1), 1.0, 1e-12);
  // A slave normal tilted like the sloping segment's opposite picks that one.
  const Vec2 slope_n = Vec2(0.2, 1).normalized();
  auto k = m.find({1, 0}, 0.5, -slope_n);
  ASSERT_TRUE(k);
  EXPECT_EQ(k->edge, 0);
  EXPECT_NEAR(k->xi, 1.0, 1e-12);
}

TEST(SegmentSearch, NodePastAConvexCornerGoesToTheVertex) {
  // A punch corner: top face y = 0 for x in [0, 1], then the side x = 1
  // going down (body below-left, walked from (1,-1) up to (1,0) then left).
  Surface m({{1, -1}, {1, 0}, {0, 0}});
  const Vec2 p(1.2, 0.2);  // in the corner's region, over neither segment
  auto h = m.find(p);
  ASSERT_TRUE(h);
  EXPECT_TRUE(h->at_vertex);
  EXPECT_NEAR((h->point - Vec2(1, 0)).norm(), 0.0, 1e-15);
  // The vertex normal bisects the corner; the gap is measured along it.
  EXPECT_NEAR(h->normal(0), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(h->normal(1), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(h->gap, 0.4 * std::sqrt(0.5), 1e-12);
  EXPECT_TRUE(h->xi == 0.0 || h->xi == 1.0);
}

TEST(SegmentSearch, SliverSegmentIsSkippedWithoutNonFiniteValues) {
  // A segment of length 1e-12 between two unit segments.
  Surface m({{2, 0}, {1 + 1e-12, 0}, {1, 0}, {0, 0}});
  for (double x0 : {1.0, 1.0 + 5e-13, 1.0 + 1e-12, 0.999, 1.001}) {
    auto h = m.find({x0, 0.01});
    ASSERT_TRUE(h) << x0;
    EXPECT_NE(h->edge, 1) << x0;
    EXPECT_TRUE(std::isfinite(h->gap) && std::isfinite(h->xi) && h->normal.allFinite()) << x0;
    EXPECT_NEAR(h->gap, 0.01, 1e-12) << x0;
    EXPECT_NEAR(h->normal(1), 1.0, 1e-4) << x0;  // the least-squares line's small tilt
  }
}

TEST(SegmentSearch, BucketGridFindsWhatAllPairsFind) {
  // A wavy surface of 400 segments; random points near it.
  std::vector<Vec2> pts;
  for (int i = 400; i >= 0; --i) pts.emplace_back(0.05 * i, 0.3 * std::sin(0.05 * i));
  Surface m(pts);
  const double capture = 0.08;
  SegmentGrid grid(m.x, m.s, capture);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0, 20), uy(-0.1, 0.1);
  int found = 0;
  for (int t = 0; t < 2000; ++t) {
    const double x0 = ux(rng);
    const Vec2 p(x0, 0.3 * std::sin(x0) + uy(rng));
    std::vector<int> cand;
    grid.candidates(p, cand);
    // Every segment within the capture distance is among the candidates.
    for (int k = 0; k < static_cast<int>(m.s.edges.size()); ++k) {
      const Vec2 a = m.x[m.s.edges[k].a], b = m.x[m.s.edges[k].b];
      const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      if ((p - (a + s * (b - a))).norm() <= capture)
        EXPECT_NE(std::find(cand.begin(), cand.end(), k), cand.end()) << t << " " << k;
    }
    EXPECT_LT(cand.size(), 40u);  // a few cells' worth, not all 400
    found += m.find(p, capture).has_value();
  }
  EXPECT_GT(found, 1500);
}

TEST(LeastSquaresLine, ThroughThreePointsAsInPaperFig3) {
  // Collinear: the line itself, xi from the coordinates along it.
  auto l = least_squares_line({0.25, 0}, {1, 0}, {0, 0});
  EXPECT_NEAR(l.xi, 0.75, 1e-12);
  EXPECT_NEAR(std::abs(l.normal(1)), 1.0, 1e-12);
  EXPECT_GT(l.normal.dot(Vec2(0, 1)), 0);  // oriented like the segment (1,0)->(0,0): outward +y
  // A slave node off the segment tilts the fitted line toward it.
  auto t = least_squares_line({0.5, 0.3}, {1, 0}, {0, 0});
  EXPECT_NEAR(t.xi, 0.5, 1e-12);
  EXPECT_NEAR(t.normal(1), 1.0, 1e-12);  // symmetric: still horizontal
  auto u = least_squares_line({0.0, 0.1}, {1, 0}, {0, 0});
  EXPECT_GT(std::abs(u.normal(0)), 0.01);  // tilted
  EXPECT_NEAR(u.normal.norm(), 1.0, 1e-12);
}
