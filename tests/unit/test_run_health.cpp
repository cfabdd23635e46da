// What a run warns of at its end (model/run_health.hpp): each warning
// counts only what crosses its limit, names the worst step, and a remeshed
// run leaves distortion to the remesher.
#include <gtest/gtest.h>

#include <string>

#include "model/run_health.hpp"

using namespace rpfem;

namespace {
std::string element(Index e) { return "element " + std::to_string(e); }
RunHealth::Limits limits(bool remeshing = false) { return {1e-7, 1e-3, 0.1, remeshing}; }
bool has(const std::vector<std::string>& w, const std::string& part) {
  for (const std::string& s : w)
    if (s.find(part) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST(RunHealth, WithinEveryLimitSaysNothing) {
  RunHealth h(limits());
  h.note_solve(1, 1e-6, RunHealth::kFloorWarning * 1e-7);  // at the floor's limit, not above
  h.note_contact(1, 0.1, RunHealth::kFrictionTolerance, "", 1e-3);
  h.note_quality(1, 0.1, 0.1, 7);
  h.note_step_error(1, 1.0, 1.0);
  EXPECT_TRUE(h.warnings(element).empty());
  EXPECT_EQ(h.min_rcond(), 1e-6);
}

TEST(RunHealth, NamesTheWorstStepOfEachKind) {
  RunHealth h(limits());
  h.note_contact(3, 0.3, 1e-6, "node 5 sticking", 2e-3);
  h.note_contact(4, 0.4, 1e-4, "node 9 slipping along its force", 5e-3);
  h.note_contact(5, 0.5, 1e-7, "node 5 again", 1e-4);
  h.note_quality(6, 0.6, 0.05, 11);
  h.note_quality(7, 0.7, 0.02, 12);
  h.note_step_error(8, 3.0, 1.0);
  h.note_step_error(9, 1.5, 1.0);
  h.note_solve(10, 1e-20, 5e-5);
  const auto w = h.warnings(element);
  ASSERT_EQ(w.size(), 5u);
  EXPECT_TRUE(has(w, "exact friction met only to 0.0001 at step 4 (stroke 0.4 mm), above 1e-08 at 3 step(s)"));
  EXPECT_TRUE(has(w, "node 9 slipping along its force"));
  EXPECT_TRUE(has(w, "penetration unacceptable: 0.005 of the element size at step 4 (stroke 0.4 mm)"));
  EXPECT_TRUE(has(w, "at 2 step(s); raise the contact penalty"));
  EXPECT_TRUE(has(w, "from step 6 (stroke 0.6 mm, element 11, 0.05), down to 0.02 at step 7 (stroke 0.7 mm, element 12)"));
  EXPECT_TRUE(has(w, "step control: 2 step(s)"));
  EXPECT_TRUE(has(w, "up to 3 times it at step 8"));
  EXPECT_TRUE(has(w, "least rcond 1e-20 at step 10 (below 100 x machine epsilon)"));
  EXPECT_TRUE(has(w, "1 step(s) solved only to the residual's round-off floor, up to 5e-05 at step 10"));
}

TEST(RunHealth, ARemeshedRunLeavesDistortionToTheRemesher) {
  RunHealth h(limits(true));
  h.note_quality(2, 0.2, 0.01, 3);
  EXPECT_TRUE(h.warnings(element).empty());
}

TEST(RunHealth, AnUnnamedFrictionViolationIsAtTheKink) {
  RunHealth h(limits());
  h.note_contact(2, 0.2, 1e-3, "", std::nullopt);
  const auto w = h.warnings(element);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_TRUE(has(w, "a row at the kink between stick and slip"));
  EXPECT_FALSE(has(w, "penetration"));
}
