// The nominal step schedule: fixed increments, or increments growing with
// the stroke (stepping.relative_increment); the planned step count the
// progress lines, sweeps and the max_steps limit use is the schedule's.
// The stepper redoes a step whose contact rows end it too deep.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "model/scene.hpp"
#include "model/stepper.hpp"

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
  // Test I's schedule: 100 steps of 0.01 mm to 1 mm, then 1 % of the
  // stroke: 181 more to 6 mm, against 600 fixed steps.
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

// Landing control's correction from the step's end: a step whose contact
// reports a row ended too deep (ContactFormulation::overshoot) is redone
// to the fraction it names, at most three times, recorded as a landing and
// not as a halving; the next step is the schedule's again.
namespace {

struct Retries : StepObserver {
  std::vector<StepRecord> steps;
  std::vector<std::pair<int, double>> retries;  // step, dt tried next
  std::vector<std::string> why;
  void on_step(const StepRecord& r) override { steps.push_back(r); }
  void on_retry(int step, double dt, const std::string& w) override {
    retries.push_back({step, dt});
    why.push_back(w);
  }
};

// No contact terms; at the second step's attempts, overshoot() hands out
// `fractions` in turn.
struct ScriptedOvershoot : ContactFormulation {
  std::vector<double> fractions;
  int steps_started = 0;
  mutable std::size_t handed = 0;
  ContactInfo info() const override { return {"none", "none", {}, {}, {}}; }
  void remember_start_gaps() override { ++steps_started; }
  std::optional<double> overshoot() const override {
    if (steps_started != 2 || handed >= fractions.size()) return std::nullopt;
    return fractions[handed++];
  }
};

Retries run_upsetting(ScriptedOvershoot& contact) {
  CaseFile file(std::string(RPFEM_SOURCE_DIR) + "/cases/upsetting_frictionless_axisym.toml",
                {"bodies.billet.mesh.nx=4", "bodies.billet.mesh.ny=4", "stepping.end_stroke=0.3",
                 "stepping.stroke_increment=0.1"});
  const Scene scene = read_scene(file);
  Retries out;
  const RunOutcome o = run_scene(scene, contact, out);
  EXPECT_TRUE(o.finished) << o.reason;
  return out;
}

}  // namespace

TEST(Stepping, AStepWhoseRowEndsTooDeepIsRedoneToTheFractionNamed) {
  ScriptedOvershoot contact;
  contact.fractions = {0.25};
  const Retries r = run_upsetting(contact);
  ASSERT_GE(r.steps.size(), 4u);  // step 0, then the steps
  const double dt = r.steps[1].dt;
  EXPECT_GT(dt, 0);
  EXPECT_FALSE(r.steps[1].landing);
  EXPECT_NEAR(r.steps[2].dt, 0.25 * dt, 1e-12 * dt);
  EXPECT_TRUE(r.steps[2].landing);
  EXPECT_EQ(r.steps[2].cuts, 0);
  EXPECT_NEAR(r.steps[3].dt, dt, 1e-12 * dt);  // the schedule's again
  ASSERT_EQ(r.retries.size(), 1u);
  EXPECT_EQ(r.retries[0].first, 2);
  EXPECT_NEAR(r.retries[0].second, 0.25 * dt, 1e-12 * dt);
  EXPECT_NE(r.why[0].find("too deep"), std::string::npos) << r.why[0];
  EXPECT_NEAR(r.steps.back().stroke, 0.3, 1e-12);
}

TEST(Stepping, AStepIsRedoneToARowsLandingThreeTimesAtMost) {
  ScriptedOvershoot contact;
  contact.fractions = {0.5, 0.5, 0.5, 0.5, 0.5};
  const Retries r = run_upsetting(contact);
  ASSERT_GE(r.steps.size(), 3u);
  EXPECT_EQ(r.retries.size(), 3u);
  EXPECT_NEAR(r.steps[2].dt, 0.125 * r.steps[1].dt, 1e-12 * r.steps[1].dt);
  EXPECT_EQ(contact.handed, 3u);  // the fourth attempt is not asked
}
