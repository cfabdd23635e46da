// Resuming a run from its state (model/stepper.hpp, run_scene's `from`):
// upsetting between frictionless flat dies under penalty, run to 2 mm at
// once and in two runs (to 1 mm, then on from its last state), gives the
// same loads and configuration from 1 mm on. The second run starts without
// the first's contact state: the enforcement finds the nodes on the die
// again in its first (instantaneous) solve.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "model/remesh.hpp"
#include "model/stepper.hpp"

using namespace rpfem;

namespace {

struct Collect : StepObserver {
  std::vector<StepRecord> steps;
  void on_step(const StepRecord& r) override { steps.push_back(r); }
};

struct Upsetting {
  Collect out;
  RunOutcome outcome;
  Upsetting(double end, const RunState* from = nullptr) {
    CaseFile file(std::string(RPFEM_SOURCE_DIR) + "/cases/upsetting_dies_frictionless_axisym.toml",
                  {"stepping.end_stroke=" + std::to_string(end), "bodies.billet.mesh.nx=6", "bodies.billet.mesh.ny=6",
                   "stepping.stroke_increment=0.1"});
    const Scene scene = read_scene(file);
    const auto contact = make_contact(file, scene, {"penalty", ""});
    outcome = run_scene(scene, *contact, out, from);
  }
};

}  // namespace

TEST(Resume, TwoRunsGiveTheLoadsOfOne) {
  const Upsetting whole(2.0), first(1.0);
  ASSERT_TRUE(whole.outcome.finished) << whole.outcome.reason;
  ASSERT_TRUE(first.outcome.finished) << first.outcome.reason;
  EXPECT_EQ(first.outcome.last.step, 10);
  EXPECT_NEAR(first.outcome.last.stroke, 1.0, 1e-12);
  const Upsetting second(2.0, &first.outcome.last);
  ASSERT_TRUE(second.outcome.finished) << second.outcome.reason;
  // The resumed run records steps 11 to 20 (step 10 is the first's).
  ASSERT_EQ(second.out.steps.size(), 10u);
  EXPECT_EQ(second.out.steps.front().step, 11);
  double load = 0, x = 0;
  for (const StepRecord& r : second.out.steps) {
    const StepRecord& w = whole.out.steps.at(r.step);
    ASSERT_EQ(w.step, r.step);
    EXPECT_NEAR(r.stroke, w.stroke, 1e-12);
    ASSERT_GT(std::abs(w.loads.at(0)(1)), 1e5);  // the die's load, N
    load = std::max(load, std::abs(r.loads.at(0)(1) / w.loads.at(0)(1) - 1));
    for (std::size_t i = 0; i < r.x.size(); ++i) x = std::max(x, (r.x[i] - w.x[i]).norm());
  }
  EXPECT_LT(load, 1e-7);
  EXPECT_LT(x, 1e-9);
  std::printf("[measured] resumed at 1 mm: load %.2e, nodes %.2e mm from the uninterrupted run\n", load, x);
}

TEST(Resume, RemeshingAHomogeneousFlowChangesNothing) {
  // The billet remeshed by gmsh at 1 mm (model/remesh.hpp): frictionless
  // upsetting is homogeneous, so every mesh carries its flow exactly and
  // the strain (uniform) comes over to round-off; the run on the new mesh
  // must give the unremeshed run's loads and volume.
  const Upsetting whole(2.0), first(1.0);
  ASSERT_TRUE(first.outcome.finished) << first.outcome.reason;
  CaseFile file(std::string(RPFEM_SOURCE_DIR) + "/cases/upsetting_dies_frictionless_axisym.toml",
                {"stepping.end_stroke=2.0", "bodies.billet.mesh.nx=6", "bodies.billet.mesh.ny=6",
                 "stepping.stroke_increment=0.1"});
  const Scene scene = read_scene(file);
  const RemeshedScene re = remesh_scene(scene, first.outcome.last, {{0}, {1.0}});
  ASSERT_NE(re.scene.mesh.num_elements(), scene.mesh.num_elements());  // a different mesh
  const auto contact = make_contact(file, re.scene, {"penalty", ""});
  Collect out;
  const RunOutcome o = run_scene(re.scene, *contact, out, &re.state);
  ASSERT_TRUE(o.finished) << o.reason;
  ASSERT_EQ(out.steps.size(), 10u);
  double load = 0, volume = 0;
  for (const StepRecord& r : out.steps) {
    const StepRecord& w = whole.out.steps.at(r.step);
    ASSERT_GT(std::abs(w.loads.at(0)(1)), 1e5);
    load = std::max(load, std::abs(r.loads.at(0)(1) / w.loads.at(0)(1) - 1));
    volume = std::max(volume, std::abs(r.volume / w.volume - 1));
  }
  // The volume at the remesh: the new mesh's against the old one's, at the
  // state's coordinates (int 2 pi r dA by Green's theorem per element).
  const auto volume_of = [](const Mesh& m, const std::vector<Vec2>& x) {
    double v = 0;
    for (const auto& q : m.quads)
      for (int k = 0; k < 4; ++k) {
        const Vec2 &p = x[q[k]], &n = x[q[(k + 1) % 4]];
        v += 2 * kPi * (p(0) + n(0)) * cross(p, n) / 6;
      }
    return v;
  };
  const double at_remesh =
      std::abs(volume_of(re.scene.mesh, re.state.x) / volume_of(scene.mesh, first.outcome.last.x) - 1);
  EXPECT_LT(load, 1e-6);
  EXPECT_LT(at_remesh, 1e-12);
  EXPECT_LT(volume, 1e-7);
  std::printf("[measured] remeshed at 1 mm (%lld -> %lld elements): load %.2e from the unremeshed run; volume %.2e "
              "at the remesh, %.2e later\n",
              static_cast<long long>(scene.mesh.num_elements()), static_cast<long long>(re.scene.mesh.num_elements()),
              load, at_remesh, volume);
}
