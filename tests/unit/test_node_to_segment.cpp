// The node-to-segment discretization (formulations/node_to_segment): the
// rows against a flat die, their contact areas and sticking bounds k w
// over the edges in contact; and the rows an instantaneous solve leaves
// out (contact/contact_model.hpp), with and without landing control; and
// the fraction of a step to redo for a row that ended it too deep.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <optional>
#include <string>

#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "contact/contact_model.hpp"
#include "factory.hpp"
#include "node_to_segment/node_to_segment.hpp"
#include "initial_view.hpp"
#include "temp_file.hpp"

using namespace rpfem;

namespace {

// An axisymmetric cylinder R = 10 mm whose top face (10 edges of 1 mm)
// touches a flat die at y = 10.
const char* kCylinder = R"(
[run]
name = "nts_areas"
geometry = "axisymmetric"
formulation = "direct"
[bodies.billet.material]
K = 300.0
n = 0.0
[bodies.billet.mesh]
shape = "rectangle"
width = 10.0
height = 10.0
nx = 10
ny = 2
[dies.top]
vy = -1.0
[[dies.top.vertex]]
x = -1.0
y = 10.0
[[dies.top.vertex]]
x = 30.0
y = 10.0
[[contact_pairs]]
body = "billet"
sides = "top"
die = "top"
[stepping]
reference = "top"
end_stroke = 1.0
stroke_increment = 0.1
)";

// The scene of a case text, its one-pass discretization and a view of its
// initial configuration (flow stress 300 MPa everywhere).
struct CylinderScene {
  CaseFile file;
  Scene scene;
  NodeToSegment disc;
  std::vector<double> flow;
  StepView view;
  explicit CylinderScene(const std::string& text)
      : file(unit::write_temp("nts_case_" + std::to_string(getpid()) + ".toml", text)), scene(read_scene(file)),
        disc(scene, file.root().section("contact"), false), flow(scene.mesh.num_elements(), 300.0) {
    view.mesh = &scene.mesh;
    view.x = view.x_from = &scene.mesh.x;
    view.flow_stress = &flow;
    view.geometry = scene.geometry;
    view.dt = 0.1;
  }
};

}  // namespace

TEST(NodeToSegment, DieRowsAreasAndStickingBounds) {
  CylinderScene s(kCylinder);
  const Scene& scene = s.scene;
  NodeToSegment& disc = s.disc;
  StepView& v = s.view;
  std::vector<ContactRow> rows;
  std::vector<std::string> events;
  disc.rows(v, rows, events);
  ASSERT_EQ(rows.size(), 11u);  // every node of the top face
  for (const ContactRow& r : rows) {
    EXPECT_EQ(r.kin.k, 1);
    EXPECT_NEAR(r.kin.gap0, 0.0, 1e-12);
    EXPECT_NEAR(r.kin.n(1), -1.0, 1e-12);  // the die's outward normal points down into the billet
    EXPECT_NEAR(r.h, 1.0, 1e-12);
  }
  std::vector<char> on(rows.size(), 1);
  std::vector<RowArea> area;
  disc.areas(v, rows, on, area);
  double A = 0, kw = 0, w = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) A += area[i].area, kw += area[i].kw, w += rows[i].weight;
  const double k = 300.0 / std::sqrt(3.0);
  EXPECT_NEAR(A, kPi * 100, 1e-9);  // pi R^2 of the face
  EXPECT_NEAR(w, kPi * 100, 1e-9);
  EXPECT_NEAR(kw, k * kPi * 100, 1e-6);
  // A node whose neighbour left the die loses that edge's area: the node at
  // r = 9 keeps its inner edge only, 2 pi int_8^9 r N(r) dr = 2 pi (2 9 + 8) / 6.
  int at10 = -1, at9 = -1;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double r = scene.mesh.x[rows[i].key](0);
    if (std::abs(r - 10) < 1e-12) at10 = static_cast<int>(i);
    if (std::abs(r - 9) < 1e-12) at9 = static_cast<int>(i);
  }
  ASSERT_GE(at10, 0);
  ASSERT_GE(at9, 0);
  on[at10] = 0;
  disc.areas(v, rows, on, area);
  EXPECT_NEAR(area[at9].area, 2 * kPi * (2 * 9 + 8) / 6.0, 1e-12);
  EXPECT_EQ(area[at10].area, 0.0);
  EXPECT_NEAR(area[at9].kw, k * area[at9].area, 1e-9);
}

namespace {

// The rows a contact model of the cylinder's case text holds after its
// begin_step on the initial configuration.
std::vector<ContactRow> model_rows(const std::string& text, bool landing_control, bool moves) {
  CaseFile file(unit::write_temp("nts_model_" + std::to_string(getpid()) + ".toml", text),
                {std::string("contact.landing_control=") + (landing_control ? "true" : "false")});
  const Scene scene = read_scene(file);
  const auto contact = make_contact(file, scene);
  std::vector<double> flow;
  StepView v = unit::initial_view(scene, flow);
  v.moves = moves;
  contact->begin_step(v);
  return dynamic_cast<const ContactModel&>(*contact).rows();
}

std::string die_at(const std::string& y) {
  std::string text = kCylinder;
  for (std::size_t at; (at = text.find("y = 10.0\n")) != std::string::npos;) text.replace(at, 9, "y = " + y + "\n");
  return text;
}

}  // namespace

TEST(ContactModel, InstantaneousSolveFreesRowsClearOfTheirMaster) {
  for (const bool control : {true, false}) {
    for (const ContactRow& r : model_rows(die_at("10.5"), control, true)) EXPECT_FALSE(r.free);
    // An instantaneous solve: a gap of 0.5 mm takes no part.
    const auto rows = model_rows(die_at("10.5"), control, false);
    ASSERT_EQ(rows.size(), 11u);
    for (const ContactRow& r : rows) {
      EXPECT_TRUE(r.free);
      EXPECT_NEAR(r.kin.gap0, 0.5, 1e-12);
      EXPECT_EQ(r.kin.gap_from, 0.0);  // only a penetration is corrected over dt
    }
    // A gap of 1e-4 of the element size: touching within a step's landing
    // band (1e-3), clear of landing control's (1e-5).
    for (const ContactRow& r : model_rows(die_at("10.0001"), control, false))
      EXPECT_EQ(r.free, control) << (control ? "with" : "without");
  }
}

TEST(ContactModel, RowsInContactKeepTheDriftBand) {
  // With landing control a slave that was free needs the narrow landing
  // band (1e-5 h) to take part in an instantaneous solve; one in contact at
  // the last solve keeps the drift band (1e-3 h), as a step's linearized
  // geometry leaves it up to that far off its master.
  CaseFile file(unit::write_temp("nts_drift_" + std::to_string(getpid()) + ".toml", kCylinder),
                {"run.formulation=penalty", "contact.landing_control=true"});
  const Scene scene = read_scene(file);
  const auto contact = make_contact(file, scene);
  const auto& model = dynamic_cast<const ContactModel&>(*contact);
  std::vector<double> flow;
  const StepView v = unit::initial_view(scene, flow);
  std::vector<Vec2> x = scene.mesh.x;
  for (Vec2& p : x) p(1) -= 1e-4;  // 1e-4 of the element size below the die
  StepView lowered = v;
  lowered.x = lowered.x_from = &x;
  lowered.moves = false;
  contact->begin_step(lowered);
  ASSERT_EQ(model.rows().size(), 11u);
  for (const ContactRow& r : model.rows()) EXPECT_TRUE(r.free);
  // The die comes down on the resting billet: every top node presses.
  const std::vector<Vec2> rest(scene.mesh.x.size(), Vec2::Zero());
  contact->begin_step(v);
  contact->settle(v, rest, rest);
  for (const RowResult& res : model.enforcement().results()) EXPECT_TRUE(res.in_contact);
  contact->begin_step(lowered);
  for (const ContactRow& r : model.rows()) EXPECT_FALSE(r.free);
}

namespace {

// The cylinder's model under penalty (beta fixed, or adaptive) with
// contact.landing_overshoot = tau, its rows' gaps remembered at the die
// height `start` (the top nodes at y = 10), then its rows with the top
// nodes raised by `rise` mm: what overshoot() returns, and the top rows'
// h and start gap.
struct Overshoot {
  std::optional<double> t;
  double h = 0, g0 = 0, g1 = 0;
};

Overshoot overshoot_after(const std::string& start, double rise, double tau, bool adapt = false) {
  CaseFile file(unit::write_temp("nts_overshoot_" + std::to_string(getpid()) + ".toml", die_at(start)),
                {"run.formulation=penalty", "contact.landing_overshoot=" + std::to_string(tau),
                 std::string("formulations.penalty.adapt=") + (adapt ? "true" : "false")});
  const Scene scene = read_scene(file);
  const auto contact = make_contact(file, scene);
  const auto& model = dynamic_cast<const ContactModel&>(*contact);
  std::vector<double> flow;
  const StepView v = unit::initial_view(scene, flow);
  contact->begin_step(v);
  Overshoot o;
  o.g0 = model.rows().at(0).kin.gap0;
  contact->remember_start_gaps();
  std::vector<Vec2> x = scene.mesh.x;
  for (Vec2& p : x)
    if (p(1) > 9.999) p(1) += rise;
  StepView end = v;
  end.x = end.x_from = &x;
  end.moves = false;
  contact->begin_step(end);
  o.h = model.rows().at(0).h, o.g1 = model.rows().at(0).kin.gap0;
  o.t = contact->overshoot();
  return o;
}

}  // namespace

TEST(ContactModel, OvershootIsTheFractionOfTheStepToRedo) {
  // A row open at the start (gap 0.5 mm) that ends 2e-3 mm deep, beyond
  // tau h: the step is redone to where its interpolated gap reaches
  // -tau h / 2, (g0 + tau h / 2) / (g0 - g1).
  const double tau = 1e-3;
  Overshoot o = overshoot_after("10.5", 0.502, tau);
  EXPECT_NEAR(o.g0, 0.5, 1e-12);
  EXPECT_NEAR(o.g1, -0.002, 1e-12);
  ASSERT_TRUE(o.t.has_value());
  EXPECT_NEAR(*o.t, (o.g0 + 0.5 * tau * o.h) / (o.g0 - o.g1), 1e-12);
  // Within tau h of the die at the end: nothing to redo.
  EXPECT_FALSE(overshoot_after("10.5", 0.5 + 0.5 * tau * o.h, tau).t.has_value());
  // A row touching at the start that ends 4e-3 mm deep: its end gap taken
  // as the step's linearization error, the step shortened by tau h / 2 /
  // (-g1).
  o = overshoot_after("10.00", 0.004, tau);  // (die_at cannot put back "10.0")
  EXPECT_NEAR(o.g0, 0.0, 1e-12);
  ASSERT_TRUE(o.t.has_value());
  EXPECT_NEAR(*o.t, 0.5 * tau * o.h / 0.004, 1e-12);
  // A row that starts deeper than it ends: the enforcement pulls it back.
  EXPECT_FALSE(overshoot_after("9.997", -0.001, tau).t.has_value());  // -0.003 -> -0.002 mm
  // The key at 0: off ...
  EXPECT_FALSE(overshoot_after("10.5", 0.6, 0.0).t.has_value());
  // ... but under the adaptive penalty, which keeps run.penetration_tolerance
  // (1e-3): the same fraction as the key at 1e-3.
  o = overshoot_after("10.5", 0.502, 0.0, true);
  ASSERT_TRUE(o.t.has_value());
  EXPECT_NEAR(*o.t, (o.g0 + 0.5 * 1e-3 * o.h) / (o.g0 - o.g1), 1e-12);
}
