// verification/suite_checks: a history_max check with a round-off floor
// column passes where each step is within the larger of the tolerance and
// its floor, and fails where one step is not; the shipped checks each say
// what they verify, against what, from which source and why their tolerance.
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

TEST(SuiteChecks, ShippedChecksSayWhatTheyVerifyAgainstWhatAndWhy) {
  const auto checks = read_suite_checks(std::string(RPFEM_SOURCE_DIR) + "/verification/checks.toml");
  ASSERT_GE(checks.size(), 65u);
  for (const SuiteCheck& c : checks) {
    const std::string what = c.scene + " " + c.formulation + " " + metric_name(c.metric);
    EXPECT_FALSE(c.verifies.empty()) << what;
    EXPECT_FALSE(c.against.empty()) << what;
    EXPECT_FALSE(c.source.empty()) << what;
    if (c.metric != CheckMetric::Finished) EXPECT_FALSE(c.why.empty()) << what;
  }
}
