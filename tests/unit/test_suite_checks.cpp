// verification/suite_checks: a history_max check with a round-off floor
// column passes where each step is within the larger of the tolerance and
// its floor, and fails where one step is not.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "suite_checks.hpp"

using namespace rpfem;

namespace {

std::string suite_with_history(const std::string& name, const std::string& csv) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "scene" / "ipopt");
  std::ofstream(dir / "scene" / "ipopt" / "history.csv") << csv;
  return dir.string();
}

SuiteCheck stationarity_check(const std::string& floor) {
  SuiteCheck c;
  c.scene = "scene", c.formulation = "ipopt", c.metric = CheckMetric::HistoryMax;
  c.column = "kkt_stationarity", c.floor = floor, c.tolerance = 1e-8;
  return c;
}

}  // namespace

TEST(SuiteChecks, HistoryMaxWithAFloorHoldsEachStepToTheLargerOfTheTwo) {
  const std::string within = suite_with_history("rpfem_unit_floor_within",
                                                "step,kkt_stationarity,kkt_round_off\n0,1e-6,3e-6\n1,5e-9,1e-10\n");
  const auto r = evaluate_suite_checks(within, {stationarity_check("kkt_round_off"), stationarity_check("")});
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(r[0].pass);
  EXPECT_DOUBLE_EQ(r[0].value, 1e-6);
  EXPECT_NE(r[0].note.find("within kkt_round_off"), std::string::npos);
  EXPECT_FALSE(r[1].pass);  // without the floor: 1e-6 > 1e-8

  // The second step is above its own floor and above the tolerance.
  const std::string above = suite_with_history("rpfem_unit_floor_above",
                                               "step,kkt_stationarity,kkt_round_off\n0,1e-6,3e-6\n1,5e-8,1e-9\n");
  const auto q = evaluate_suite_checks(above, {stationarity_check("kkt_round_off")});
  EXPECT_FALSE(q[0].pass);
}
