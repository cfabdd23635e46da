// Conformance of every contact treatment: one problem run through every
// enforcement x discretization that applies to it, in-process on tiny
// scenes (after MFEM's tests/unit/linalg/test_constrainedsolver.cpp, one
// problem through every constrained solver):
//   a block pressed between two flat dies (friction: none, factor, Coulomb;
//   under ipopt also both laws exact),
//   two stacked blocks with non-matching meshes (contact between bodies;
//   friction: none, factor, Coulomb; under ipopt also both laws exact),
//   one element on a floor die with a known multiplier.
// Each combination must finish with its contact state settled; its contact
// forces must sum to its die loads (and cancel between bodies); its terms'
// gradient and Hessian must match finite differences of its energy and
// gradient; the exact multiplier must come out; and without friction
// direct, auglag and ipopt must agree, with the penalty converging to them
// at first order in 1 / beta.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <ostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "factory.hpp"
#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "model/step_problem.hpp"
#include "model/stepper.hpp"
#include "ssn/ssn_step_solver.hpp"
#include "temp_file.hpp"

using namespace rpfem;

namespace {

// A plane-strain block, 2 x 1 mm (x = 0 a symmetry plane), pressed at
// 1 mm/s by a flat top die onto a fixed flat floor die.
std::string die_block(const std::string& friction) {
  return R"(
[run]
name = "conformance_dies"
geometry = "plane_strain"
formulation = "direct"
[bodies.block.material]
K = 100.0
n = 0.0
m = 0.1
rate_ref = 0.5
[bodies.block.mesh]
shape = "rectangle"
width = 2.0
height = 1.0
nx = 4
ny = 2
[[symmetry]]
normal = "x"
[dies.floor]
[[dies.floor.vertex]]
x = 5.0
y = 0.0
[[dies.floor.vertex]]
x = -1.0
y = 0.0
[dies.top]
vy = -1.0
[[dies.top.vertex]]
x = -1.0
y = 1.0
[[dies.top.vertex]]
x = 5.0
y = 1.0
)" + friction + R"(
[[contact_pairs]]
body = "block"
sides = "bottom"
die = "floor"
[[contact_pairs]]
body = "block"
sides = "top"
die = "top"
[stepping]
reference = "top"
end_stroke = 0.1
stroke_increment = 0.05
)";
}

// Two stacked blocks, 2 x 0.5 mm each, meshed independently (4 and 3
// edges at the interface), between frictionless platens.
const char* kTwoBlocks = R"(
[run]
name = "conformance_bodies"
geometry = "plane_strain"
formulation = "penalty"
[bodies.lower.material]
K = 100.0
n = 0.0
m = 0.1
rate_ref = 0.5
[bodies.lower.mesh]
shape = "rectangle"
width = 2.0
height = 0.5
nx = 4
ny = 2
[[bodies.lower.velocity]]
name = "bottom"
side = "bottom"
vy = 0.0
[bodies.upper.material]
K = 100.0
n = 0.0
m = 0.1
rate_ref = 0.5
[bodies.upper.mesh]
shape = "rectangle"
y0 = 0.5
width = 2.0
height = 0.5
nx = 3
ny = 2
[[bodies.upper.velocity]]
name = "top"
side = "top"
vy = -1.0
[[symmetry]]
normal = "x"
[[contact_pairs]]
body = "lower"
sides = "top"
with = "upper"
with_sides = "bottom"
[stepping]
reference = "top"
end_stroke = 0.1
stroke_increment = 0.05
)";

// One element, 1 x 1 mm, perfectly plastic (K = 100 MPa), x = 0 a
// symmetry plane, pressed at 1 mm/s onto a fixed frictionless floor die:
// sigma_yy = -(2 / sqrt 3) K everywhere, the floor pressure exactly.
const char* kOneElement = R"(
[run]
name = "conformance_multiplier"
geometry = "plane_strain"
formulation = "direct"
[bodies.block.material]
K = 100.0
n = 0.0
[bodies.block.mesh]
shape = "rectangle"
width = 1.0
height = 1.0
nx = 1
ny = 1
[[bodies.block.velocity]]
name = "top"
side = "top"
vy = -1.0
[[symmetry]]
normal = "x"
[dies.floor]
[[dies.floor.vertex]]
x = 3.0
y = 0.0
[[dies.floor.vertex]]
x = -1.0
y = 0.0
[[contact_pairs]]
body = "block"
sides = "bottom"
die = "floor"
[stepping]
reference = "top"
end_stroke = 0.1
stroke_increment = 0.05
)";

struct Collect : StepObserver {
  std::vector<std::string> load_names;
  std::vector<StepRecord> steps;
  void on_start(const DerivedParameters&, const std::vector<std::string>& loads,
                const std::vector<std::string>&) override {
    load_names = loads;
  }
  void on_step(const StepRecord& r) override { steps.push_back(r); }
  Vec2 load(const std::string& name, std::size_t step) const {
    for (std::size_t i = 0; i < load_names.size(); ++i)
      if (load_names[i] == name) return steps.at(step).loads.at(i);
    ADD_FAILURE() << "no load " << name;
    return Vec2::Zero();
  }
};

// A scene with its contact treatment, run to its end.
struct ContactRun {
  std::unique_ptr<CaseFile> file;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<ContactFormulation> contact;
  Collect out;
  RunOutcome outcome;
  ContactRun(const std::string& text, const std::string& enforcement, const std::string& discretization,
      const std::vector<std::string>& set = {}) {
    // One file per process and run (ctest runs the cases in parallel).
    static int count = 0;
    const std::string path =
        unit::write_temp("conformance_" + std::to_string(getpid()) + "_" + std::to_string(count++) + ".toml", text);
    file = std::make_unique<CaseFile>(path, set);
    scene = std::make_unique<Scene>(read_scene(*file));
    contact = make_contact(*file, *scene, {enforcement, discretization});
    outcome = run_scene(*scene, *contact, out);
  }
};

// Collects the terms' energy, gradient and (dense) Hessian; the elements'
// nodal forces it hands out (TermSink::element_force) are fixed ones.
struct Dense : TermSink {
  double energy = 0;
  Vec grad;
  Mat hess;
  const std::vector<Vec2>* forces = nullptr;
  explicit Dense(Index n, const std::vector<Vec2>* f = nullptr)
      : grad(Vec::Zero(2 * n)), hess(Mat::Zero(2 * n, 2 * n)), forces(f) {}
  Vec2 element_force(Index node) const override { return forces ? (*forces)[node] : Vec2::Zero(); }
  void add(const Index* nodes, int k, double e, const double* g, const double* H) override {
    energy += e;
    for (int a = 0; a < k; ++a)
      for (int i = 0; i < 2; ++i) {
        grad(2 * nodes[a] + i) += g[2 * a + i];
        for (int b = 0; b < k; ++b)
          for (int j = 0; j < 2; ++j) hess(2 * nodes[a] + i, 2 * nodes[b] + j) += H[(2 * b + j) * 2 * k + 2 * a + i];
      }
  }
};

struct Combination {
  std::string scene, enforcement, discretization, friction;
};

void PrintTo(const Combination& c, std::ostream* os) {
  *os << c.scene << " " << c.enforcement << "+" << c.discretization << " friction " << c.friction;
}

// A friction table's keys: "factor" or "coulomb", "_exact" for the exact law.
std::string friction_keys(const std::string& law) {
  const std::string exact = law.size() > 6 && law.substr(law.size() - 6) == "_exact" ? "regularization = \"exact\"\n" : "";
  if (law.rfind("factor", 0) == 0) return "law = \"factor\"\nm = 0.3\n" + exact;
  if (law.rfind("coulomb", 0) == 0) return "law = \"coulomb\"\nmu = 0.2\n" + exact;
  return "";
}

std::string scene_text(const Combination& c) {
  if (c.scene == "dies") return die_block(c.friction);
  if (c.scene == "bodies") {
    // Friction between the blocks: the pair's own law.
    if (c.friction == "none") return kTwoBlocks;
    return std::string(kTwoBlocks) + "[contact_pairs.friction]\n" + friction_keys(c.friction);
  }
  return kOneElement;
}

std::string friction_table(const std::string& law) {
  return law == "none" ? "" : "[dies.top.friction]\n" + friction_keys(law);
}

std::vector<Combination> combinations() {
  std::vector<Combination> out;
  for (const auto& d : discretizations()) {
    for (const auto& e : formulations()) {
      // ipopt treats friction by the arctan law (its default) or exactly.
      std::vector<std::string> laws{"none", "factor", "coulomb"};
      if (e.name == "ipopt") laws.insert(laws.end(), {"factor_exact", "coulomb_exact"});
      if (e.dies)
        for (const std::string& law : laws) {
          out.push_back({"dies", e.name, d.name, law});
          if (law == "none") out.push_back({"multiplier", e.name, d.name, law});
        }
      if (e.bodies && !(e.refuses_overconstrained && d.overconstrains))
        for (const std::string& law : laws) out.push_back({"bodies", e.name, d.name, law});
    }
  }
  return out;
}

std::string label(const testing::TestParamInfo<Combination>& p) {
  return p.param.scene + "_" + p.param.enforcement + "_" + p.param.discretization + "_" + p.param.friction;
}

// The step after `last`, at its configuration (the reference speed is 1 mm/s).
StepView next_step(const Scene& scene, const StepRecord& last) {
  StepView view;
  view.mesh = &scene.mesh;
  view.x = view.x_from = &last.x;
  view.flow_stress = &last.flow_stress;
  view.geometry = scene.geometry;
  view.time = view.time_from = last.time;
  view.dt = scene.stepping.stroke_increment;
  view.step = last.step + 1;
  return view;
}

class Conformance : public testing::TestWithParam<Combination> {};

TEST_P(Conformance, SettlesBalancesAndHasExactDerivatives) {
  const Combination& c = GetParam();
  ContactRun run(c.scene == "dies" ? die_block(friction_table(c.friction)) : scene_text(c), c.enforcement,
                 c.discretization);
  ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
  const Scene& scene = *run.scene;
  const auto& steps = run.out.steps;
  ASSERT_GE(steps.size(), 3u);
  // The contact state settles: every step well within the kernel's passes.
  for (const auto& s : steps) EXPECT_LE(s.contact_passes, 30) << "step " << s.step;
  for (const auto& s : steps) {
    const double scale = std::max(1.0, s.contact_force.empty() ? 0.0 : [&] {
      double m = 0;
      for (const Vec2& f : s.contact_force) m = std::max(m, f.norm());
      return m;
    }());
    if (c.scene == "bodies") {
      // Between bodies action equals reaction: the contact forces cancel.
      Vec2 sum = Vec2::Zero();
      for (const Vec2& f : s.contact_force) sum += f;
      EXPECT_LT(sum.norm(), 1e-9 * scale) << "step " << s.step;
      continue;
    }
    // A die's load is the contact force on its side's nodes (the mirrored
    // half of the block doubles its y component; x cancels).
    for (const std::string side : {"top", "bottom"}) {
      const std::string die = side == "top" ? "top" : "floor";
      if (c.scene == "multiplier" && die == "top") continue;
      double fy = 0;
      std::vector<char> on(scene.mesh.num_nodes(), 0);
      for (const Edge& e : scene.mesh.sides.at("block." + side)) on[e.a] = on[e.b] = 1;
      for (Index n = 0; n < scene.mesh.num_nodes(); ++n)
        if (on[n]) fy += s.contact_force[n](1);
      EXPECT_NEAR(run.out.load(die, s.step)(1), 2 * fy, 1e-9 * scale) << die << " at step " << s.step;
    }
  }
  // An enforcement that measures its Kuhn-Tucker and friction conditions
  // meets them at every step: penetration over the element size, |N r|
  // and the friction law (force within the bound, at it and opposing the
  // slip where slipping; slip rate where sticking, over the speed scale).
  const ContactInfo info = run.contact->info();
  const std::map<std::string, double> kkt_tolerance{
      {"kkt_primal", 1e-9}, {"kkt_complementarity", 1e-8}, {"kkt_friction", 1e-8}, {"kkt_stick_slip", 1e-8}};
  for (std::size_t k = 0; k < info.column_names.size(); ++k) {
    const auto tol = kkt_tolerance.find(info.column_names[k]);
    if (tol == kkt_tolerance.end() || c.enforcement == "auglag") continue;  // auglag: its own tolerance, an augmentation limit
    for (const auto& s : steps) EXPECT_LE(s.contact_report[k], tol->second) << tol->first << " at step " << s.step;
  }
  if (c.scene == "multiplier") {
    // The floor nodes' pressure is the exact stress (2 / sqrt 3) K.
    const double exact = 2.0 / std::sqrt(3.0) * 100.0;
    for (const auto& s : steps)
      for (Index n = 0; n < scene.mesh.num_nodes(); ++n)
        if (std::abs(s.x[n](1)) < 1e-12)
          EXPECT_NEAR(s.node_fields.at("contact_pressure")[n], exact, 1e-6 * exact) << "node " << n;
  }

  // The terms at the last configuration, at its velocities and nearby:
  // gradient against the energy's finite differences (a potential), Hessian
  // against the gradient's (the consistent tangent).
  const StepRecord& last = steps.back();
  const StepView view = next_step(scene, last);
  run.contact->begin_step(view);
  const Index n = scene.mesh.num_nodes();
  const TangentKind kind = run.contact->tangent();
  for (double shift : {0.0, 0.05}) {
    std::vector<Vec2> v = last.v;
    for (Index i = 0; i < n; ++i) v[i] += shift * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
    // The last step's contact forces as the elements' nodal forces, fixed
    // (direct's live Coulomb bound reads its reaction there; the coupling
    // to the velocities is the kernel's, DirectCoulombTangentIsTheResiduals
    // Derivative). One evaluation first: a solve's first uses the last
    // bounds.
    const std::vector<Vec2>& forces = last.contact_force;
    Dense first(n, &forces);
    run.contact->add_terms(view, v, first);
    Dense at(n, &forces);
    run.contact->anchor_merit(view, v);
    run.contact->add_terms(view, v, at);
    const double h = 1e-7;
    const double gscale = std::max(1.0, at.grad.cwiseAbs().maxCoeff());
    const double hscale = std::max(1.0, at.hess.cwiseAbs().maxCoeff());
    for (Index k = 0; k < 2 * n; ++k) {
      std::vector<Vec2> vp = v, vm = v;
      vp[k / 2](k % 2) += h;
      vm[k / 2](k % 2) -= h;
      Dense p(n, &forces), m(n, &forces);
      run.contact->add_terms(view, vp, p);
      run.contact->add_terms(view, vm, m);
      if (kind.potential || kind.merit)
        EXPECT_NEAR(at.grad(k), (p.energy - m.energy) / (2 * h), 1e-5 * gscale) << "gradient, dof " << k;
      const Vec fd = (p.grad - m.grad) / (2 * h);
      for (Index i = 0; i < 2 * n; ++i)
        EXPECT_NEAR(at.hess(i, k), fd(i), 1e-5 * hscale) << "Hessian (" << i << ", " << k << ")";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryCombination, Conformance, testing::ValuesIn(combinations()), label);

// An enforcement whose rows' forces are unknowns refuses a discretization
// that over-constrains between bodies, naming the key.
TEST(Conformance, OverconstrainedRowsAreRefusedByName) {
  for (const auto& e : formulations()) {
    if (!e.refuses_overconstrained) continue;
    for (const auto& d : discretizations()) {
      if (!d.overconstrains) continue;
      try {
        ContactRun run(kTwoBlocks, e.name, d.name);
        ADD_FAILURE() << e.name << "+" << d.name << " ran";
      } catch (const InputError& err) {
        EXPECT_NE(std::string(err.what()).find("contact.discretization"), std::string::npos) << err.what();
      }
    }
  }
}

// Frictionless, the enforcements meet the same Kuhn-Tucker conditions:
// direct, auglag and ipopt agree, and the penalty converges to them at
// first order in 1 / beta.
TEST(Conformance, FrictionlessEnforcementsAgreeToFirstOrderInOneOverBeta) {
  const std::string text = die_block("");
  const auto final_load = [&](const std::string& e, const std::vector<std::string>& set) {
    ContactRun run(text, e, "", set);
    EXPECT_TRUE(run.outcome.finished) << e << ": " << run.outcome.reason;
    return run.out.load("top", run.out.steps.size() - 1)(1);
  };
  const double direct = final_load("direct", {});
  EXPECT_NEAR(final_load("auglag", {}), direct, 1e-6 * std::abs(direct));
  EXPECT_NEAR(final_load("ipopt", {}), direct, 1e-6 * std::abs(direct));
  const double d1 = std::abs(final_load("penalty", {"formulations.penalty.beta_factor=1e-2"}) - direct);
  const double d2 = std::abs(final_load("penalty", {"formulations.penalty.beta_factor=1e-1"}) - direct);
  EXPECT_GT(d1, 1e-9 * std::abs(direct));  // measurable at 1e-2 of the default
  EXPECT_NEAR(std::log10(d1 / d2), 1.0, 0.2) << d1 << " " << d2;
}

// The step after a run's last at its configuration, begun by the run's
// contact, as a StepProblem with the contact's constraints (every element
// at strain 0.1, volumetric penalty 1e4; fext: the nodes' external forces,
// zero if empty). Not moved: the problem refers to its members.
struct NextStep {
  StepView view;
  std::vector<std::array<double, 4>> strain;
  std::vector<ElementMaterial> materials;
  std::vector<Vec2> fext;
  SolverWorkspace ws{LinearSolverChoice::Auto};
  std::unique_ptr<StepProblem> problem;
  NextStep(ContactRun& run, std::vector<Vec2> external = {})
      : view(next_step(*run.scene, run.out.steps.back())),
        strain(run.scene->mesh.num_elements(), {0.1, 0.1, 0.1, 0.1}),
        materials(run.scene->mesh.num_elements(), {&run.scene->bodies[0].law, 1e4, 0.0}),
        fext(external.empty() ? std::vector<Vec2>(run.scene->mesh.num_nodes(), Vec2::Zero()) : std::move(external)) {
    run.contact->begin_step(view);
    problem = std::make_unique<StepProblem>(view, strain, materials, 1e-3, fext, *run.contact, ws);
    std::vector<NodeConstraint> cons;
    run.contact->constraints(view, cons);
    problem->set_constraints(cons);
  }
};

// Coulomb under direct: the bound mu N follows the node's reaction N = n .
// F_s within Newton, and the kernel's tangent carries its derivative (the
// elements' Hessian rows of the node, TermSink::add_force_coupling). The
// step's assembled tangent against central differences of its residual,
// at the solved velocities of the last step and nearby.
TEST(Conformance, DirectCoulombTangentIsTheResidualsDerivative) {
  ContactRun run(die_block(friction_table("coulomb")), "direct", "");
  ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
  const Scene& scene = *run.scene;
  const StepRecord& last = run.out.steps.back();
  NextStep next(run);
  StepProblem& problem = *next.problem;
  std::vector<Index> force_nodes;
  run.contact->force_nodes(next.view, force_nodes);
  ASSERT_FALSE(force_nodes.empty()) << "no Coulomb row follows its reaction";
  EXPECT_FALSE(run.contact->tangent().symmetric);
  for (double shift : {0.0, 0.02}) {
    std::vector<Vec2> v = last.v;
    for (Index i = 0; i < scene.mesh.num_nodes(); ++i) v[i] += shift * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
    const Vec u = problem.dofs().reduce(v);
    problem.tangent(u, true);  // a solve's first tangent: the last bound; from then on live
    const Mat A = Mat(problem.tangent(u, true));
    Vec R, Rp, Rm;
    double scale = 0;
    problem.residual(u, R, scale);
    const double h = 1e-7;
    double coupled = 0;  // how far the tangent is from symmetric: the coupling is in it
    for (Index i = 0; i < A.rows(); ++i)
      for (Index j = 0; j < A.cols(); ++j) coupled = std::max(coupled, std::abs(A(i, j) - A(j, i)));
    EXPECT_GT(coupled, 1e-6 * A.cwiseAbs().maxCoeff());
    for (Index k = 0; k < u.size(); ++k) {
      Vec up = u, um = u;
      up(k) += h, um(k) -= h;
      problem.residual(up, Rp, scale);
      problem.residual(um, Rm, scale);
      const Vec fd = (Rp - Rm) / (2 * h);
      for (Index i = 0; i < u.size(); ++i)
        EXPECT_NEAR(A(i, k), fd(i), 1e-5 * A.cwiseAbs().maxCoeff()) << "tangent (" << i << ", " << k << ")";
    }
  }
}

// The line search's trial (StepProblem::residual_energy: forces and
// energy from one element pass) gives the bits of residual() and
// energy(), with a potential contact (penalty, friction factor) and away
// from the solution.
TEST(Conformance, ResidualAndEnergyInOnePassAreTheTwoCallsBits) {
  ContactRun run(die_block(friction_table("factor")), "penalty", "");
  ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
  const Scene& scene = *run.scene;
  const StepRecord& last = run.out.steps.back();
  std::vector<Vec2> fext(scene.mesh.num_nodes(), Vec2::Zero());
  fext[0] = Vec2(3.0, -2.0);  // the external power's term too
  NextStep next(run, fext);
  StepProblem& problem = *next.problem;
  ASSERT_TRUE(problem.newton_system().residual_energy) << "penalty has a potential";
  for (double shift : {0.0, 0.05}) {
    std::vector<Vec2> v = last.v;
    for (Index i = 0; i < scene.mesh.num_nodes(); ++i) v[i] += shift * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
    const Vec u = problem.dofs().reduce(v);
    Vec R1, R2;
    double s1 = 0, s2 = 0;
    problem.residual(u, R1, s1);
    const double e1 = problem.energy(u);
    const double e2 = problem.residual_energy(u, R2, s2);
    EXPECT_EQ(e1, e2) << "shift " << shift;
    EXPECT_EQ(s1, s2);
    ASSERT_EQ(R1.size(), R2.size());
    EXPECT_EQ((R1 - R2).cwiseAbs().maxCoeff(), 0.0) << "shift " << shift;
    EXPECT_GT(R1.norm(), 0.0);
  }
}

// A Newton full-step trial keeps the consistent tangent's element terms
// (StepProblem::keep_tangent_terms): the trial's forces and energy are the
// bits of a plain one, and the tangent at that very u, scattered from them,
// is the bits of one from its own element pass; a tangent at another u,
// after a change of the limiting rate or of the constraints, or a secant
// one, makes its own pass. With a potential (penalty, friction factor) and
// with Coulomb under direct (its force nodes read the elements' forces and
// Hessian rows in the tangent).
TEST(Conformance, KeptTangentTermsGiveTheTangentsBits) {
  for (const auto& [law, enforcement] : {std::pair<std::string, std::string>{"factor", "penalty"},
                                         std::pair<std::string, std::string>{"coulomb", "direct"}}) {
    SCOPED_TRACE(law + " under " + enforcement);
    ContactRun run(die_block(friction_table(law)), enforcement, "");
    ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
    const Scene& scene = *run.scene;
    NextStep next(run);
    StepProblem& problem = *next.problem;
    std::vector<Vec2> v0 = run.out.steps.back().v, v1 = v0;
    for (Index i = 0; i < scene.mesh.num_nodes(); ++i) v1[i] += 0.05 * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
    const Vec u0 = problem.dofs().reduce(v0), u1 = problem.dofs().reduce(v1);
    const auto bits = [](const SpMat& a, const SpMat& b) {
      return a.nonZeros() == b.nonZeros() && (Eigen::MatrixXd(a) - Eigen::MatrixXd(b)).cwiseAbs().maxCoeff() == 0.0;
    };
    // Direct's Coulomb bounds are live from a solve's second tangent on
    // (its first takes the last solve's): the tangents compared are later.
    problem.tangent(u1, true);
    const SpMat fresh = problem.tangent(u1, true);
    const SolverWorkspace& ws = next.ws;
    Vec R_plain, R_kept, R0;
    double s_plain = 0, s_kept = 0, s0 = 0;
    problem.residual(u1, R_plain, s_plain);
    problem.keep_tangent_terms(true);
    problem.residual(u1, R_kept, s_kept);
    problem.keep_tangent_terms(false);
    EXPECT_EQ((R_plain - R_kept).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(s_plain, s_kept);
    problem.residual(u0, R0, s0);  // a plain residual elsewhere leaves the kept terms
    int passes = ws.tangent_passes, from_trials = ws.tangents_from_trials;
    EXPECT_TRUE(bits(problem.tangent(u1, true), fresh));
    EXPECT_EQ(ws.tangents_from_trials, from_trials + 1);
    EXPECT_EQ(ws.tangent_passes, passes);
    // Kept terms serve one tangent only, at their u, consistent, with the
    // same limiting rate and constraints.
    const auto keep_at = [&](const Vec& u) {
      problem.keep_tangent_terms(true);
      problem.residual(u, R0, s0);
      problem.keep_tangent_terms(false);
    };
    from_trials = ws.tangents_from_trials;
    EXPECT_TRUE(bits(problem.tangent(u1, true), fresh));  // used already
    keep_at(u0);
    EXPECT_TRUE(bits(problem.tangent(u1, true), fresh));  // another u
    keep_at(u1);
    const SpMat secant = problem.tangent(u1, false);
    EXPECT_FALSE(bits(secant, fresh));
    // The same constraints again (a contact pass that changed none): u
    // maps to the same velocities, the terms stay; other constraints in
    // between drop them.
    keep_at(u1);
    std::vector<NodeConstraint> cons;
    run.contact->constraints(next.view, cons);
    problem.set_constraints(cons);
    EXPECT_TRUE(bits(problem.tangent(u1, true), fresh));
    EXPECT_EQ(ws.tangents_from_trials, ++from_trials);
    keep_at(u1);
    Index free_node = 0;
    while (problem.dofs().frame(free_node).nfree < 2) ++free_node;
    std::vector<NodeConstraint> other = cons;
    other.push_back({free_node, Vec2(1, 0), 0.0});
    problem.set_constraints(other);
    problem.set_constraints(cons);
    EXPECT_TRUE(bits(problem.tangent(u1, true), fresh));
    EXPECT_EQ(ws.tangents_from_trials, from_trials);
    keep_at(u1);
    problem.set_limiting_strain_rate(0.5 * problem.limiting_strain_rate());
    const SpMat slower = problem.tangent(u1, true);
    EXPECT_EQ(ws.tangents_from_trials, from_trials);
    keep_at(u1);
    EXPECT_TRUE(bits(problem.tangent(u1, true), slower));
    EXPECT_EQ(ws.tangents_from_trials, from_trials + 1);
  }
}


// An element pass at the velocities of the last one (a solve's forces
// after its last trial, a contact pass that starts where the last ended)
// takes that pass's results: the same bits as running it, counted in
// force_passes_reused; other velocities, a new limiting rate or another
// problem's pass in between run it again.
TEST(Conformance, ForcesAtTheLastPassVelocitiesAreItsBits) {
  ContactRun run(die_block(friction_table("factor")), "penalty", "");
  ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
  const Scene& scene = *run.scene;
  NextStep next(run);
  StepProblem& problem = *next.problem;
  const SolverWorkspace& ws = next.ws;
  std::vector<Vec2> v0 = run.out.steps.back().v, v1 = v0;
  for (Index i = 0; i < scene.mesh.num_nodes(); ++i) v1[i] += 0.05 * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
  const Vec u0 = problem.dofs().reduce(v0), u1 = problem.dofs().reduce(v1);
  const auto same = [](const Vec& a, const Vec& b) { return a.size() == b.size() && (a - b).cwiseAbs().maxCoeff() == 0.0; };
  // Reference values, each from a problem of its own.
  const auto fresh = [&](const Vec& u, Vec& R, double& scale) {
    NextStep other(run);
    other.problem->residual(u, R, scale);
    return other.problem->energy(u);
  };
  Vec R1, R0;
  double s1 = 0, s0 = 0;
  const double e1 = fresh(u1, R1, s1);
  fresh(u0, R0, s0);

  Vec R;
  double s = 0;
  const int passes = ws.force_passes, reused = ws.force_passes_reused;
  problem.residual(u1, R, s);
  EXPECT_TRUE(same(R, R1));
  EXPECT_EQ(ws.force_passes, passes + 1);
  problem.residual(u1, R, s);  // the last pass's velocities
  EXPECT_TRUE(same(R, R1));
  EXPECT_EQ(s, s1);
  EXPECT_EQ(problem.residual_energy(u1, R, s), e1);
  EXPECT_TRUE(same(R, R1));
  EXPECT_EQ(ws.force_passes, passes + 1);
  EXPECT_EQ(ws.force_passes_reused, reused + 2);
  // Kept terms asked for at those velocities: a pass of their own.
  problem.keep_tangent_terms(true);
  problem.residual(u1, R, s);
  problem.keep_tangent_terms(false);
  EXPECT_EQ(ws.force_passes, passes + 2);
  // Other velocities in between.
  problem.residual(u0, R, s);
  EXPECT_TRUE(same(R, R0));
  problem.residual(u1, R, s);
  EXPECT_TRUE(same(R, R1));
  EXPECT_EQ(ws.force_passes, passes + 4);
  // Another problem's pass on the same workspace in between.
  StepProblem second(next.view, next.strain, next.materials, 1e-3, next.fext, *run.contact, next.ws);
  second.residual(u0, R, s);
  problem.residual(u1, R, s);
  EXPECT_TRUE(same(R, R1));
  EXPECT_EQ(ws.force_passes, passes + 6);
  // A new limiting rate (above the block's strain rates): other forces,
  // from a new pass.
  problem.set_limiting_strain_rate(1e4 * problem.limiting_strain_rate());
  problem.residual(u1, R, s);
  EXPECT_EQ(ws.force_passes, passes + 7);
  EXPECT_FALSE(same(R, R1));
  EXPECT_EQ(ws.force_passes_reused, reused + 2);
}

}  // namespace

// The semi-smooth Newton enforcement's system: its generalized Jacobian
// (the kernel's tangent, the rows' weights and the complementarity
// functions' derivatives) is the whole residual's derivative, at points
// on every branch (rows pressing and open, sticking and slipping either
// way), against dies and between bodies, node to segment and mortar.
TEST(Conformance, SsnJacobianIsTheResidualsDerivative) {
  for (const std::string disc : {"node_to_segment", "mortar"})
    for (const std::string scene : {"dies", "bodies"})
      for (const std::string law : {"factor", "coulomb"}) {
        SCOPED_TRACE(scene + " " + disc + " " + law);
        const Combination c{scene, "ssn", disc, law};
        ContactRun run(scene == "dies" ? die_block(friction_table(law)) : scene_text(c), "ssn", disc);
        ASSERT_TRUE(run.outcome.finished) << run.outcome.reason;
        NextStep next(run);
        auto* ssn = dynamic_cast<SsnStepSolver*>(run.contact->solver());
        ASSERT_NE(ssn, nullptr);
        const StepRecord& last = run.out.steps.back();
        const Index n = next.problem->dofs().num_free();
        Vec F;
        Vec x = Vec::Zero(n);
        ssn->system(next.view, *next.problem, x, F);  // the rows in the solve
        const std::size_t m = ssn->rows_in_solve();
        ASSERT_GT(m, 1u);
        x.resize(n + 2 * static_cast<Index>(m));
        std::vector<Vec2> v = last.v;
        for (std::size_t i = 0; i < v.size(); ++i) v[i] += 0.03 * Vec2(std::sin(1.0 + i), std::cos(2.0 * i));
        x.head(n) = next.problem->dofs().reduce(v);
        // Forces of the size the rows carry, on every branch.
        for (std::size_t j = 0; j < m; ++j) {
          x[n + 2 * j] = (j % 3 == 2 ? -1.0 : 1.0) * (20.0 + 7.0 * j);
          x[n + 2 * j + 1] = (j % 2 ? 1.0 : -1.0) * (j % 4 < 2 ? 0.5 : 15.0);
        }
        const Mat J = Mat(ssn->system(next.view, *next.problem, x, F));
        const double scale = J.cwiseAbs().maxCoeff(), h = 1e-7;
        for (Index k = 0; k < x.size(); ++k) {
          Vec xp = x, xm = x, Fp, Fm;
          xp(k) += h, xm(k) -= h;
          ssn->system(next.view, *next.problem, xp, Fp);
          ssn->system(next.view, *next.problem, xm, Fm);
          const Vec fd = (Fp - Fm) / (2 * h);
          for (Index i = 0; i < x.size(); ++i) EXPECT_NEAR(J(i, k), fd(i), 1e-5 * scale) << "J(" << i << ", " << k << ")";
        }
      }
}

// The friction law's treatment is each enforcement's to accept: the exact
// law is refused by those that treat friction by the arctan law only, and
// the arctan law by ssn, each with one line naming the key; ipopt takes
// both.
TEST(Conformance, FrictionTreatmentAnEnforcementCannotDoIsRefusedByName) {
  const std::string exact = "[dies.top.friction]\nlaw = \"factor\"\nm = 0.3\nregularization = \"exact\"\n";
  const std::string arctan = "[dies.top.friction]\nlaw = \"coulomb\"\nmu = 0.2\nregularization = \"arctan\"\n";
  for (const auto& e : formulations()) {
    if (!e.dies) continue;
    for (const std::string& table : {exact, arctan}) {
      bool refused = false;
      try {
        ContactRun run(die_block(table), e.name, "");
      } catch (const InputError& err) {
        refused = true;
        const std::string what = err.what();
        EXPECT_NE(what.find("dies.top.friction.regularization"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      }
      // ssn treats friction exactly only, ipopt either way, the others by
      // the arctan law only.
      const bool takes = e.name == "ipopt" || (table == exact) == (e.name == "ssn");
      EXPECT_EQ(refused, !takes) << e.name << ": " << table;
    }
  }
}

// The ssn rows condensed onto the nodes pressing on dies (CHOLMOD on the
// tangent with their directions prescribed) take the same Newton steps as
// the saddle-point system: the same loads, and the condensed steps used.
TEST(Conformance, SsnCondensedRowsGiveTheSaddlePointSystemsSolution) {
  for (const std::string law : {"none", "factor"}) {
    SCOPED_TRACE(law);
    ContactRun on(die_block(friction_table(law)), "ssn", "", {"formulations.ssn.condense=true"});
    ContactRun off(die_block(friction_table(law)), "ssn", "", {"formulations.ssn.condense=false"});
    ASSERT_TRUE(on.outcome.finished && off.outcome.finished);
    ASSERT_EQ(on.out.steps.size(), off.out.steps.size());
    for (std::size_t k = 1; k < on.out.steps.size(); ++k) {
      const double a = on.out.load("top", k)(1), b = off.out.load("top", k)(1);
      EXPECT_NEAR(a, b, 1e-9 * std::abs(b)) << "step " << k;
    }
    const ContactInfo info = on.contact->info();
    const auto col = std::find(info.column_names.begin(), info.column_names.end(), "ssn_condensed");
    ASSERT_NE(col, info.column_names.end());
    double condensed = 0;
    for (const auto& s : on.out.steps) condensed += s.contact_report[col - info.column_names.begin()];
    EXPECT_GT(condensed, 0);
  }
}

// Rows between bodies (two blocks, the friction factor: open, sticking
// and slipping rows) solved by the augmented Lagrangian on K give the
// saddle-point system's LU loads to the solves' tolerance, and the path is
// taken (a count of none fails).
TEST(Conformance, SsnAugmentedStepsGiveTheSaddlePointSystemsSolution) {
  for (const std::string law : {"none", "factor"}) {
    const std::string text =
        law == "none" ? std::string(kTwoBlocks) : std::string(kTwoBlocks) + "[contact_pairs.friction]\n" + friction_keys(law);
    ContactRun on(text, "ssn", "", {"formulations.ssn.augmented=true", "formulations.ssn.condense=false"});
    ContactRun off(text, "ssn", "", {"formulations.ssn.augmented=false", "formulations.ssn.condense=false"});
    ASSERT_TRUE(on.outcome.finished && off.outcome.finished) << law;
    ASSERT_EQ(on.out.steps.size(), off.out.steps.size());
    for (std::size_t k = 1; k < on.out.steps.size(); ++k) {
      const double a = on.out.load("top", k)(1), b = off.out.load("top", k)(1);
      EXPECT_NEAR(a, b, 1e-8 * std::abs(b)) << law << " step " << k;
    }
    const ContactInfo info = on.contact->info();
    const auto col = std::find(info.column_names.begin(), info.column_names.end(), "ssn_augmented");
    ASSERT_NE(col, info.column_names.end());
    double augmented = 0;
    for (const auto& s : on.out.steps) augmented += s.contact_report[col - info.column_names.begin()];
    EXPECT_GT(augmented, 0) << law;
  }
}

// ssn's own iteration count is the step's: under the midpoint scheme the
// half-step solve's and the end solve's together, as the step's Newton
// iterations count them (a count of the last solve only fails).
TEST(Conformance, SsnIterationsCountEverySolveOfTheStep) {
  ContactRun run(die_block(friction_table("factor")), "ssn", "", {"stepping.integration=midpoint"});
  ASSERT_TRUE(run.outcome.finished);
  const ContactInfo info = run.contact->info();
  const auto col = std::find(info.column_names.begin(), info.column_names.end(), "ssn_iterations");
  ASSERT_NE(col, info.column_names.end());
  for (std::size_t k = 1; k < run.out.steps.size(); ++k) {
    const StepRecord& s = run.out.steps[k];
    EXPECT_EQ(s.solves, 2) << "step " << k;
    EXPECT_EQ(s.contact_report[col - info.column_names.begin()], double(s.newton_iterations)) << "step " << k;
  }
}
