// The nominal step schedule: fixed increments, or increments growing with
// the stroke (stepping.relative_increment); the planned step count the
// progress lines, sweeps and the max_steps limit use is the schedule's.
#include <gtest/gtest.h>

#include "model/scene.hpp"

using namespace rpfem;

namespace {
// The steps the stepper takes without landings or cuts: each from the
// stroke reached, its increment at that stroke, the last one short.
int walked_steps(const SteppingSpec& s) {
  int n = 0;
  for (double x = 0; x < s.end_stroke - 1e-12 * s.end_stroke; ++n) x += std::min(s.increment_at(x), s.end_stroke - x);
  return n;
}
}  // namespace

TEST(Stepping, PlannedStepsAreTheSchedulesSteps) {
  SteppingSpec s;
  for (const double end : {0.05, 0.3, 1.0, 6.0, 12.0}) {
    for (const double inc : {0.01, 0.05, 0.1}) {
      for (const double rel : {0.0, 0.005, 0.01, 0.2}) {
        s.end_stroke = end, s.stroke_increment = inc, s.relative_increment = rel;
        // The closed form may count one step more than the walk where a
        // step ends within round-off of the end.
        const int walked = walked_steps(s);
        EXPECT_GE(s.planned_steps(), walked) << end << " " << inc << " " << rel;
        EXPECT_LE(s.planned_steps(), walked + 1) << end << " " << inc << " " << rel;
      }
    }
  }
  // Test I at 1 % of the stroke: 100 steps of 0.01 mm to 1 mm, then 181
  // more to 6 mm, against 600 fixed steps.
  s.end_stroke = 6.0, s.stroke_increment = 0.01, s.relative_increment = 0.01;
  EXPECT_EQ(walked_steps(s), 281);
  s.relative_increment = 0;
  EXPECT_EQ(walked_steps(s), 600);
  EXPECT_EQ(s.planned_steps(), 600);
}

TEST(Stepping, TheIncrementIsTheLargerOfTheFixedAndTheRelative) {
  SteppingSpec s;
  s.stroke_increment = 0.01, s.relative_increment = 0.01;
  EXPECT_DOUBLE_EQ(s.increment_at(0.0), 0.01);
  EXPECT_DOUBLE_EQ(s.increment_at(0.5), 0.01);
  EXPECT_DOUBLE_EQ(s.increment_at(5.0), 0.05);
}
