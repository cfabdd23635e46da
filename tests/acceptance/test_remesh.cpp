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
  EXPECT_LT(worst, 5e-3);  // the 0.5 %
  // Nine remeshes (every 0.5 mm, none at the end), each with its measures.
  const std::string summary = read_text(dir + "/summary.json");
  int remeshes = 0;
  for (std::size_t p = 0; (p = summary.find("\"strain_integral_change\"", p)) != std::string::npos; ++p) ++remeshes;
  EXPECT_EQ(remeshes, 9);
  // The body is homogeneously deformed: a remesh changes the load solved
  // at its configuration by the solves' tolerance only (the 1e-6).
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
  EXPECT_NE(events.find("10,0.5,remesh (remesh.stroke_interval reached)"), std::string::npos) << events;
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
