// Remeshing in a run ([remesh], src/app/remeshing_run): frictionless
// upsetting between flat dies (cases/upsetting_dies_frictionless_axisym
// .toml, direct, 50 %) remeshed every 10 steps stays at the exact load,
// each remesh recorded as an event and in summary.json with its volume
// change (none: the mesher keeps the outline) and the load's jump (none:
// the body deforms homogeneously); result.h5 holds each new mesh and its steps name it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "analytic.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

// Under each enforcement: the contact state each keeps (nodes on the dies,
// multipliers, Ipopt's start) is found again on the new mesh in the
// resumed run's first solve, at the remesh's configuration.
class Remesh : public ::testing::TestWithParam<const char*> {};

//~ feature = "remeshing"
//~ scene = "upsetting_dies_frictionless_axisym remeshed every 0.5 mm, under direct, penalty, auglag and ipopt"
//~ source = "Kobayashi, Oh and Altan 1989, sec. 5.2 (the exact load)"
//~ [[check]]
//~ what = "die load against the exact load at every step, 101 rows (one per step across the remeshes)"
//~ compares = "exact solution"
//~ tolerance = "5e-3 (relative)"
//~ why = "the kernel's tolerance for homogeneous upsetting: a remesh must not add a visible error"
//~ [[check]]
//~ what = "nine remeshes recorded, each with its load jump: the new mesh's load at the remesh's configuration against the old one's"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-6 (relative)"
//~ why = "the body deforms homogeneously, so the new mesh carries the same load to the solves' tolerance; a wrong field transfer or contact state shows as per cents"
//~ [[check]]
//~ what = "the remesh event in events.csv; the new meshes and their steps in result.h5"
//~ compares = "expected behaviour"
//~ tolerance = "present"
//~ why = "every remesh is recorded where a reader looks for it"
TEST_P(Remesh, UpsettingRemeshedEveryTenStepsKeepsTheExactLoad) {
  const std::string dir = run_case("upsetting_dies_frictionless_axisym",
                                   "--set remesh.enabled=true --set remesh.stroke_interval=0.5 "
                                   "--set stepping.output_every=5 --formulation " + std::string(GetParam()));
  const History h = read_history(dir + "/history.csv");
  ASSERT_EQ(h.rows(), 101u);  // one row per step, the remeshes' segments continuing
  EXPECT_NEAR(h.at("stroke").back(), 5.0, 1e-9);
  const FlowStressLaw l = accept::aisi1035();
  double worst = 0, volume = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    const double H = 20.0 - 2 * h.at("stroke")[i];
    worst = std::max(worst, std::abs(-h.at("top_die.Fy")[i] / upsetting_load_axisymmetric(l, 20, 20, H) - 1));
    volume = std::max(volume, std::abs(h.at("volume_change")[i]));
  }
  EXPECT_LT(worst, 5e-3);  // 0.5 %, as without remeshing
  // Nine remeshes (every 0.5 mm, none at the end), each with its measures.
  const std::string summary = read_text(dir + "/summary.json");
  int remeshes = 0;
  for (std::size_t p = 0; (p = summary.find("\"strain_integral_change\"", p)) != std::string::npos; ++p) ++remeshes;
  EXPECT_EQ(remeshes, 9);
  // The body is homogeneously deformed: a remesh changes the load solved
  // at its configuration by the solves' tolerance only (1e-6).
  int jumps = 0;
  double largest_jump = 0;
  for (std::size_t p = 0; (p = summary.find("\"load_jump\"", p)) != std::string::npos; ++p) {
    ++jumps;
    const double jump = std::strtod(summary.c_str() + summary.find(':', p) + 1, nullptr);
    EXPECT_LT(std::abs(jump), 1e-6) << "remesh " << jumps;
    largest_jump = std::max(largest_jump, std::abs(jump));
  }
  EXPECT_EQ(jumps, 9);
  const std::string events = read_text(dir + "/events.csv");
  EXPECT_NE(events.find("10,0.5,kept,remesh (remesh.stroke_interval reached)"), std::string::npos) << events;
  // The new meshes in result.h5: the first remesh's from step 11 on.
  std::vector<unsigned long long> shape;
  read_h5_dataset(dir + "/result.h5", "/meshes/000011/connectivity", &shape);
  ASSERT_EQ(shape.size(), 2u);
  EXPECT_GT(shape[0], 0u);
  read_h5_dataset(dir + "/result.h5", "/steps/000015/coordinates", &shape);
  EXPECT_GT(shape[0], 0u);
  std::printf("[measured] upsetting remeshed every 10 steps (%s): load %.2e from the exact one at worst; volume "
              "change %.2e at worst; a remesh's own load jump %.2e at most\n",
              GetParam(), worst, volume, largest_jump);
}

INSTANTIATE_TEST_SUITE_P(Enforcements, Remesh, ::testing::Values("direct", "penalty", "auglag", "ipopt"));

// Contact between bodies taken over at a remesh: Test I's two spheres under
// one pass (mortar's dual rows; `finer` keeps its slave), remeshed by force
// at 1 mm. The rows found where the spheres touched start in contact on the
// new meshes, their gaps held as their zero. Without that, each sphere's
// new outline leaves the new slave nodes off the other's new surface by
// what one pass leaves (the master's nodes inside the slave), the roles of
// the two equal spheres swap by round-off, and the load on the new mesh at
// the same configuration falls by 28.8 %, coming back over three landing
// steps.
class RemeshBodies : public ::testing::TestWithParam<const char*> {};

//~ feature = "remeshing"
//~ scene = "paper_test1_double_action_remeshed, remeshed at 1 mm, one pass with dual mortar rows (penalty+mortar, ipopt+mortar)"
//~ source = "Puso and Laursen 2004 (mortar rows); paper Test I (Fig. 5-7)"
//~ [[check]]
//~ what = "the remesh's load jump, and against the load's trend"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-2 (relative)"
//~ why = "without the contact taken over the load falls 28.8 % on the new mesh and comes back over three landing steps; with it the jump is within the 1 % any remesh of a non-homogeneous field is allowed (RemeshScenes)"
//~ [[check]]
//~ what = "gaps held as the rows' zero: above 0, below 0.1 h; penetration / h"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "held < 0.1; penetration 1e-3"
//~ why = "the held gaps are one pass's own misfit, a few thousandths of h; the enforcement's penetration from them stays within the penalty's tolerance"
TEST_P(RemeshBodies, ContactBetweenBodiesIsTakenOver) {
  const std::string dir = run_case("paper_test1_double_action_remeshed",
                                   "--set remesh.stroke_interval=1 --set stepping.end_stroke=1.05 --formulation " +
                                       std::string(GetParam()));
  const std::string summary = read_text(dir + "/summary.json");
  const std::size_t p = summary.find("\"load_jump\"");
  ASSERT_NE(p, std::string::npos) << summary;
  const double jump = std::strtod(summary.c_str() + summary.find(':', p) + 1, nullptr);
  EXPECT_LT(std::abs(jump), 1e-2);  // 1 %
  const std::size_t q = summary.find("\"load_jump_trend\"");
  ASSERT_NE(q, std::string::npos) << summary;
  const double trend = std::strtod(summary.c_str() + summary.find(':', q) + 1, nullptr);
  EXPECT_LT(std::abs(trend), 1e-2);
  const std::string events = read_text(dir + "/events.csv");
  EXPECT_NE(events.find("contact taken over on upper-lower"), std::string::npos) << events;
  // The gaps held are one pass's own misfit, a few thousandths of the size;
  // the enforcement's penetration from them stays within the tolerance.
  const History h = read_history(dir + "/history.csv");
  double held = 0, pen = 0;
  for (std::size_t i = 0; i < h.rows(); ++i)
    held = std::max(held, h.at("held_gap_rel")[i]), pen = std::max(pen, h.at("max_penetration_rel")[i]);
  EXPECT_GT(held, 0);
  EXPECT_LT(held, 0.1);
  EXPECT_LT(pen, 1e-3);
  std::printf("[measured] Test I remeshed at 1 mm (%s): load jump %.2e, against the trend %.2e; gaps held up to "
              "%.2e h, penetration %.2e h\n",
              GetParam(), jump, trend, held, pen);
}

INSTANTIATE_TEST_SUITE_P(OnePass, RemeshBodies, ::testing::Values("penalty+mortar", "ipopt+mortar"));

//~ feature = "remeshing"
//~ scene = "ring_compression_remeshed (24 x 16: 384 elements) under direct with run.max_elements = 400; its first remesh, at 1.45 mm, makes 468"
//~ source = "run.max_elements (docs/case-format.md): the case's meshes and every remesh's within it"
//~ [[check]]
//~ what = "the run stops at the remesh, exit code 3, the reason naming the new mesh's size and run.max_elements, the steps before it saved"
//~ compares = "expected behaviour"
//~ tolerance = "exact"
//~ why = "a size from the error can refine without bound; a run past the limit it was given would take memory it was told not to"
TEST(RemeshLimits, AMeshPastMaxElementsStopsTheRun) {
  const std::string dir =
      run_case("ring_compression_remeshed", "--formulation direct --set run.max_elements=400", 3);
  const std::string summary = read_text(dir + "/summary.json");
  EXPECT_NE(summary.find("the new mesh has 468 elements"), std::string::npos) << summary;
  EXPECT_NE(summary.find("expected at most run.max_elements = 400"), std::string::npos) << summary;
  const History h = read_history(dir + "/history.csv");
  ASSERT_GT(h.rows(), 1u);
  EXPECT_NEAR(h.at("stroke")[h.rows() - 1], 1.45, 1e-9);  // the step the remesh followed
}

//~ feature = "remeshing"
//~ scene = "ring_compression_remeshed (24 x 16) under direct with remesh.min_scaled_jacobian = 0.95 and remesh.reject_below = 0.9: each new mesh (least scaled Jacobian about 0.6) falls below the floor within its first step, whose halvings take it a 64th of an increment"
//~ source = "the remeshing driver (src/app/remeshing_run.cpp): five remeshes in a row must advance the stroke by one step's increment"
//~ [[check]]
//~ what = "the run stops with exit code 3 at its fifth remesh without advance, the reason naming the strokes, the increment and remesh.reject_below, the steps before it saved"
//~ compares = "expected behaviour"
//~ tolerance = "exact"
//~ why = "a run whose remeshes crawl would otherwise go on to remesh.max_remeshes, hours on a fine mesh, and end short anyway"
TEST(RemeshLimits, RemeshesThatDoNotAdvanceStopTheRun) {
  const std::string dir = run_case("ring_compression_remeshed",
                                   "--formulation direct --set remesh.min_scaled_jacobian=0.95 --set remesh.reject_below=0.9",
                                   3, "_crawl");
  const std::string summary = read_text(dir + "/summary.json");
  EXPECT_NE(summary.find("remeshing does not advance: the last 5 remeshes took the stroke from 0.7 to 0.70"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("less than one step's increment (0.05 mm)"), std::string::npos) << summary;
  EXPECT_NE(summary.find("remesh.reject_below = 0.9"), std::string::npos) << summary;
  const History h = read_history(dir + "/history.csv");
  ASSERT_GT(h.rows(), 1u);
  EXPECT_LT(h.at("stroke")[h.rows() - 1], 0.71);
  EXPECT_GT(h.at("stroke")[h.rows() - 1], 0.7);
}
