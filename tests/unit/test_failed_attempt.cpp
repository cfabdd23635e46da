// A step's attempt that is not kept leaves no trace in the contact state
// (ContactFormulation::save_state): the retry at half the step starts from
// the state the step started from, and the failed attempt's events are
// reported as such (StepObserver::on_discarded).
//
// Test I's single action under direct elimination, landing control off, so
// nodes touch the dies within steps. In one run the first attempt at a
// step is made to fail after a solve of it settled a contact event (a node
// now held on the die); in the other, at the same step, before any solve
// of it settled. Both runs then take that step at half length from the
// same start and must agree from there on: configuration, loads, contact
// events and iterations. A retry that kept the failed attempt's contact
// state starts with that node held on the die, and its touch is missing
// from the step's events (measured: the configurations agreed to the bit
// either way, direct's converged state not depending on its passes' start).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "model/stepper.hpp"

using namespace rpfem;

namespace {

struct Collect : StepObserver {
  std::vector<StepRecord> steps;
  std::vector<std::pair<int, std::vector<std::string>>> discarded;
  void on_step(const StepRecord& r) override { steps.push_back(r); }
  void on_discarded(int step, const std::vector<std::string>& events) override { discarded.push_back({step, events}); }
};

// Forwards every call to `inner`, and makes a solve fail (its own solver,
// reporting no convergence) while `failing`.
struct Forwarding : ContactFormulation {
  struct Failing : StepSolver {
    SolveOutcome solve(const StepView&, StepProblem&, Vec&) override { return {false, 0, 0, "forced to fail"}; }
  };
  ContactFormulation& inner;
  bool failing = false;
  Failing fail;
  explicit Forwarding(ContactFormulation& c) : inner(c) {}

  ContactInfo info() const override { return inner.info(); }
  void begin_step(const StepView& v) override { inner.begin_step(v); }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override {
    return inner.settle(v, vel, F);
  }
  StepSolver* solver() override { return failing ? &fail : inner.solver(); }
  bool fall_back() override { return !failing && inner.fall_back(); }
  void constraints(const StepView& v, std::vector<NodeConstraint>& out) const override { inner.constraints(v, out); }
  void couplings(const StepView& v, std::vector<std::vector<Index>>& out) const override { inner.couplings(v, out); }
  void force_nodes(const StepView& v, std::vector<Index>& out) const override { inner.force_nodes(v, out); }
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& s) const override {
    inner.add_terms(v, vel, s);
  }
  TangentKind tangent() const override { return inner.tangent(); }
  void anchor_merit(const StepView& v, const std::vector<Vec2>& vel) override { inner.anchor_merit(v, vel); }
  std::optional<double> limit_dt(const StepView& v, const std::vector<Vec2>& vel) const override {
    return inner.limit_dt(v, vel);
  }
  void remember_start_gaps() override { inner.remember_start_gaps(); }
  std::optional<double> overshoot() const override { return inner.overshoot(); }
  double place_on_surfaces(const StepView& v, std::vector<Vec2>& x) override { return inner.place_on_surfaces(v, x); }
  void end_step(const StepView& v, const std::vector<Vec2>& vel) override { inner.end_step(v, vel); }
  std::any save_state() const override { return inner.save_state(); }
  void restore_state(const std::any& s) override { inner.restore_state(s); }
  ContactZones contact_zones(const std::vector<Vec2>& x) const override { return inner.contact_zones(x); }
  void take_over(const ContactZones& z) override { inner.take_over(z); }
  ContactRecord record(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) const override {
    return inner.record(v, vel, F);
  }
};

// At step `step` makes the first attempt's solves fail, from the solve
// after the first settle that reported an event (after_change) or from the
// step's first solve, until the next solve starts (the retry's).
struct FailOnce : Forwarding {
  int step;
  bool after_change;
  bool armed = true, failed = false;
  FailOnce(ContactFormulation& c, int k, bool after) : Forwarding(c), step(k), after_change(after) {}

  void begin_step(const StepView& v) override {
    if (failing) failing = false, failed = true;  // the failed attempt is over
    if (armed && !after_change && v.step == step) armed = false, failing = true;
    inner.begin_step(v);
  }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override {
    StepCheck c = inner.settle(v, vel, F);
    if (armed && after_change && v.step == step && !c.events.empty()) {
      armed = false, failing = true;
      c.resolve = true;  // solved again: by the failing solver
    }
    return c;
  }
};

// Test I's single action, coarse, to 1 mm in steps of 0.1 mm; `more`:
// further overrides.
CaseFile sphere_case(bool landing_control, const std::vector<std::string>& more = {}) {
  std::vector<std::string> set = {"bodies.sphere.mesh.n=4", "bodies.sphere.mesh.layers=4", "stepping.end_stroke=1.0",
                                  "stepping.stroke_increment=0.1", "stepping.relative_increment=0.0",
                                  std::string("contact.landing_control=") + (landing_control ? "true" : "false"),
                                  "contact.landing_overshoot=0.0"};
  set.insert(set.end(), more.begin(), more.end());
  return CaseFile(std::string(RPFEM_SOURCE_DIR) + "/cases/paper_test1_single_action.toml", set);
}

struct SphereRun {
  Collect out;
  RunOutcome outcome;
  bool failed = false;
  // step < 0: no failure.
  SphereRun(int step, bool after_change) {
    CaseFile file = sphere_case(false);
    const Scene scene = read_scene(file);
    const auto contact = make_contact(file, scene, {"direct", ""});
    FailOnce wrapped(*contact, step, after_change);
    outcome = run_scene(scene, wrapped, out);
    failed = wrapped.failed;
  }
};

bool touches(const StepRecord& r) {
  return std::any_of(r.events.begin(), r.events.end(), [](const std::string& e) { return e.find("touch") == 0; });
}

}  // namespace

TEST(FailedAttempt, TheRetryStartsFromTheStepsContactState) {
  // The first step (after the second) at which a node touches a die.
  const SphereRun probe(-1, false);
  ASSERT_TRUE(probe.outcome.finished) << probe.outcome.reason;
  int k = -1;
  for (const StepRecord& r : probe.out.steps)
    if (r.step >= 2 && touches(r)) {
      k = r.step;
      break;
    }
  ASSERT_GT(k, 0) << "no touch within a step: the scene no longer tests this";
  const SphereRun changed(k, true), clean(k, false);
  ASSERT_TRUE(changed.failed && clean.failed);
  ASSERT_TRUE(changed.outcome.finished) << changed.outcome.reason;
  ASSERT_TRUE(clean.outcome.finished) << clean.outcome.reason;
  // The failed attempt's touch is reported as a discarded attempt's.
  const auto discarded_touch = [&](const SphereRun& r) {
    for (const auto& [step, events] : r.out.discarded)
      if (step == k)
        for (const std::string& e : events)
          if (e.find("touch") == 0) return true;
    return false;
  };
  EXPECT_TRUE(discarded_touch(changed));
  EXPECT_FALSE(discarded_touch(clean));
  ASSERT_EQ(changed.out.steps.size(), clean.out.steps.size());
  double dx = 0, load = 0;
  for (std::size_t i = 0; i < clean.out.steps.size(); ++i) {
    const StepRecord &a = changed.out.steps[i], &b = clean.out.steps[i];
    ASSERT_EQ(a.step, b.step);
    EXPECT_NEAR(a.stroke, b.stroke, 1e-12);
    if (a.step == k) EXPECT_EQ(a.cuts, 1);
    // The same contact events and the same work: a leaked state shows as
    // a release of the node the failed attempt touched, and more passes.
    EXPECT_EQ(a.events, b.events) << "step " << a.step;
    EXPECT_EQ(a.contact_passes, b.contact_passes) << "step " << a.step;
    EXPECT_EQ(a.newton_iterations, b.newton_iterations) << "step " << a.step;
    for (std::size_t n = 0; n < a.x.size(); ++n) dx = std::max(dx, (a.x[n] - b.x[n]).norm());
    for (std::size_t l = 0; l < a.loads.size(); ++l)
      load = std::max(load, (a.loads[l] - b.loads[l]).norm() / std::max(b.loads[l].norm(), 1.0));
  }
  std::printf("[measured] failed attempt at step %d after a touch: retry's run %.2e mm, loads %.2e (relative) from the "
              "run whose attempt failed before any contact change\n",
              k, dx, load);
  EXPECT_LT(dx, 1e-9);
  EXPECT_LT(load, 1e-7);
}

namespace {

// Every solve of an attempt that ends at a landing (StepView::at_landing)
// fails: an enforcement that cannot settle a row landing at the step's end.
struct FailAtLanding : Forwarding {
  int failures = 0;
  using Forwarding::Forwarding;
  void begin_step(const StepView& v) override {
    failing = v.at_landing;
    failures += failing;
    inner.begin_step(v);
  }
};

}  // namespace

// A step that fails ending at a landing is tried once past it, at its
// nominal length: no halvings, and no later step ends at that landing again
// (halved, the step ends short of the landing, and the next one, shortened
// to it, fails the same way: 13 failed attempts a landing on the remeshed
// ring under ssn).
TEST(FailedAttempt, AStepFailingAtALandingIsTriedPastIt) {
  // No halving allowed: the retry past the landing is none.
  CaseFile file = sphere_case(true, {"stepping.max_cuts=0"});
  const Scene scene = read_scene(file);
  const auto clean_contact = make_contact(file, scene, {"direct", ""});
  Collect clean;
  const RunOutcome clean_outcome = run_scene(scene, *clean_contact, clean);
  ASSERT_TRUE(clean_outcome.finished) << clean_outcome.reason;
  const long landings =
      std::count_if(clean.steps.begin(), clean.steps.end(), [](const StepRecord& r) { return r.landing; });
  ASSERT_GT(landings, 0) << "no step ends at a landing: the scene no longer tests this";

  const auto contact = make_contact(file, scene, {"direct", ""});
  FailAtLanding wrapped(*contact);
  Collect out;
  const RunOutcome outcome = run_scene(scene, wrapped, out);
  ASSERT_TRUE(outcome.finished) << outcome.reason;
  EXPECT_GT(wrapped.failures, 0);
  EXPECT_EQ(outcome.total_cuts, 0);
  EXPECT_NEAR(out.steps.back().stroke, 1.0, 1e-9);
  for (const StepRecord& r : out.steps) {
    EXPECT_EQ(r.cuts, 0) << "step " << r.step;
    EXPECT_FALSE(r.landing) << "step " << r.step;
  }
  // Each failed landing is followed by the step at its nominal length.
  EXPECT_LE(out.steps.size(), clean.steps.size());
  std::printf("[measured] %ld landing steps in the clean run; %d solves failed at a landing, %zu steps against %zu, "
              "no halvings\n",
              landings, wrapped.failures, out.steps.size(), clean.steps.size());
}
