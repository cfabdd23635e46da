// The adaptive penalty's raise (src/contact/adaptive_penalty.*): a row that
// ends a step deeper than the tolerance has its factor multiplied by the
// ratio the penalty's compliance (d = N dt / beta) asks for to end at half
// the tolerance, up to the cap; rows within the tolerance, free rows and
// other identities keep theirs; a re-solve that does not halve the depth
// is not raised again and its raise is taken back; the factors outlive
// the step, the count does not.
#include <gtest/gtest.h>

#include <vector>

#include "contact/adaptive_penalty.hpp"

using namespace rpfem;

namespace {

ContactRow row(int iface, Index key, double depth_rel, double h = 0.5, bool free = false) {
  ContactRow r;
  r.iface = iface;
  r.key = key;
  r.h = h;
  r.kin.gap0 = -depth_rel * h;
  r.free = free;
  return r;
}

AdaptivePenalty adaptive(bool on = true, double cap = 1e3) { return AdaptivePenalty({on, 1e-3, cap}); }

}  // namespace

TEST(AdaptivePenalty, RaisesTheRowsTooDeepByTheRatioToHalfTheTolerance) {
  AdaptivePenalty a = adaptive();
  a.begin_step();
  const std::vector<ContactRow> rows = {row(0, 7, 3e-3), row(0, 8, 0.9e-3), row(1, 7, 5e-3, 0.5, true),
                                        row(1, 9, -1.0)};  // open
  const PenaltyRaise r = a.raise(rows);
  EXPECT_EQ(r.rows, 1);
  EXPECT_DOUBLE_EQ(r.depth, 3e-3);  // the free row is not measured
  EXPECT_NEAR(a.factor(rows[0]), 6.0, 1e-12);  // 3e-3 / (0.5 x 1e-3)
  EXPECT_EQ(a.factor(rows[1]), 1.0);
  EXPECT_EQ(a.factor(rows[2]), 1.0);  // same key, another interface
  EXPECT_NEAR(r.largest_factor, 6.0, 1e-12);
  EXPECT_EQ(a.raises(), 1);
  // The re-solve met the tolerance: nothing more, the factor kept.
  const PenaltyRaise again = a.raise({row(0, 7, 0.4e-3), row(0, 8, 0.9e-3)});
  EXPECT_EQ(again.rows, 0);
  EXPECT_NEAR(a.factor(rows[0]), 6.0, 1e-12);
  // The next step: the count starts over, the factor stays.
  a.begin_step();
  EXPECT_EQ(a.raises(), 0);
  EXPECT_NEAR(a.largest_factor(), 6.0, 1e-12);
  // A raised row raised again multiplies its factor.
  EXPECT_EQ(a.raise({row(0, 7, 2e-3)}).rows, 1);
  EXPECT_NEAR(a.factor(rows[0]), 24.0, 1e-12);
}

TEST(AdaptivePenalty, StopsAtTheCapAndWhenTheDepthDoesNotFollowThePenalty) {
  AdaptivePenalty a = adaptive(true, 100);
  a.begin_step();
  const ContactRow deep = row(0, 1, 0.2);
  EXPECT_EQ(a.raise({deep}).rows, 1);
  EXPECT_DOUBLE_EQ(a.factor(deep), 100.0);  // 400 asked, capped
  // At the cap: no raise, no re-solve.
  a.begin_step();
  EXPECT_EQ(a.raise({deep}).rows, 0);

  // A re-solve that leaves more than half the depth: the depth is not the
  // penalty's compliance, raised no further.
  AdaptivePenalty b = adaptive();
  b.begin_step();
  EXPECT_EQ(b.raise({row(0, 1, 4e-3), row(0, 2, 1.5e-3)}).rows, 2);
  // ... and the raise that did not help is taken back.
  EXPECT_EQ(b.raise({row(0, 1, 3e-3), row(0, 2, 1.5e-3)}).rows, 0);
  EXPECT_EQ(b.factor(row(0, 1, 0)), 1.0);
  EXPECT_EQ(b.factor(row(0, 2, 0)), 1.0);
  EXPECT_EQ(b.largest_factor(), 1.0);
  // Halved: raised again.
  b.begin_step();
  EXPECT_EQ(b.raise({row(0, 1, 4e-3)}).rows, 1);
  EXPECT_EQ(b.raise({row(0, 1, 1.9e-3)}).rows, 1);
  EXPECT_EQ(b.raises(), 2);
}

TEST(AdaptivePenalty, OffNeverRaises) {
  AdaptivePenalty a = adaptive(false);
  a.begin_step();
  const PenaltyRaise r = a.raise({row(0, 1, 0.1)});
  EXPECT_EQ(r.rows, 0);
  EXPECT_DOUBLE_EQ(r.depth, 0.1);
  EXPECT_EQ(a.factor(row(0, 1, 0)), 1.0);
}
