// A case's [expect] tables (verification/expectations.hpp): read and
// validated, the runs they need planned without repeats, and evaluated on
// run folders written here by hand.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "expectations.hpp"
#include "temp_file.hpp"

using namespace rpfem;
namespace fs = std::filesystem;

namespace {

// A case with its own expectation, two variants and references: the
// case's own formulation named explicitly (the case's run), a variant's
// overrides given as reference_set (that variant's run), and ipopt.
const char* kCase = R"(
[run]
formulation = "penalty"
[expect]
outcome = "finished"
[[expect.measure]]
what = "load_difference"
load = "top.Fy"
reference_formulation = "ipopt"
max = 1e-3
[[variants]]
name = "stiff"
set = ["formulations.penalty.beta_factor=1e12"]
expect = { outcome = "stopped", reason_contains = ["ill-conditioned"] }
[[variants]]
name = "soft"
set = ["solver.alpha=1e2"]
[variants.expect]
outcome = "finished"
warnings = ["penetration"]
[[variants.expect.measure]]
what = "load_difference"
load = "top.Fy"
reference_formulation = "penalty"
max = 1e-2
[[variants.expect.measure]]
what = "load_difference"
load = "top.Fy"
reference_set = ["solver.alpha=1e2"]
max = 1
[[variants.expect.measure]]
what = "history_max"
column = "volume_change"
min = 1e-3
max = 1e-2
)";

void write_run(const std::string& dir, const std::string& status, const std::string& extra,
               const std::string& history) {
  fs::create_directories(dir);
  std::ofstream(dir + "/summary.json") << "{\n    \"parameters\" : { \"warnings\" : [\"not this one\"] },\n"
                                       << "    \"status\" : \"" << status << "\"" << extra << "\n}\n";
  std::ofstream(dir + "/history.csv") << "step,stroke,top.Fy,volume_change\n" << history;
}

}  // namespace

TEST(Expectations, PlansEachRunOnce) {
  const ExpectedCase c = read_expected_case(unit::write_temp("expect_plan.toml", kCase));
  ASSERT_EQ(c.expectations.size(), 3u);
  // case, stiff, soft, then ipopt: the other two references are runs already planned.
  ASSERT_EQ(c.runs.size(), 4u);
  EXPECT_EQ(c.runs[0].label, "case");
  EXPECT_EQ(c.runs[1].variant, "stiff");
  EXPECT_EQ(c.runs[3].label, "reference-1");
  EXPECT_EQ(c.runs[3].formulation, "ipopt");
  EXPECT_EQ(c.expectations[0].measures[0].reference, 3);
  EXPECT_EQ(c.expectations[2].measures[0].reference, 0);  // penalty: the case's own
  EXPECT_EQ(c.expectations[2].measures[1].reference, 2);  // alpha 1e2: the variant
  const auto args = c.runs[3].arguments();
  EXPECT_NE(std::find(args.begin(), args.end(), "ipopt"), args.end());
}

TEST(Expectations, BadKeysNameFileAndKey) {
  const auto fails = [](const std::string& name, const std::string& text, const std::string& what) {
    try {
      read_expected_case(unit::write_temp(name, text));
      ADD_FAILURE() << "no error for " << name;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(name), std::string::npos) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
    }
  };
  fails("expect_bad1.toml", "[expect]\noutcome = \"maybe\"\n", "'expect.outcome'");
  fails("expect_bad2.toml", "[expect]\noutcome = \"finished\"\nreason = [\"x\"]\n", "'expect.reason'");
  fails("expect_bad3.toml", "[expect]\noutcome = \"finished\"\nreason_contains = [\"x\"]\n",
        "'expect.reason_contains': only with outcome = \"stopped\"");
  fails("expect_bad4.toml", "[expect]\noutcome = \"finished\"\n[[expect.measure]]\nwhat = \"history_max\"\ncolumn = \"x\"\n",
        "give the bounds");
  fails("expect_bad5.toml",
        "[expect]\noutcome = \"finished\"\n[[expect.measure]]\nwhat = \"summary\"\nkey = \"x\"\nmax = \"big\"\n",
        "'expect.measure.0.max': expected a number");
  fails("expect_bad6.toml", "[run]\ngeometry = \"axisymmetric\"\n", "no [expect] table");
}

TEST(Expectations, EvaluatesOutcomeWarningsBoundsAndFiniteness) {
  const std::string dir = (fs::temp_directory_path() / "rpfem_unit_expect").string();
  fs::remove_all(dir);
  const ExpectedCase c = read_expected_case(unit::write_temp("expect_eval.toml", kCase));
  write_run(dir + "/case", "finished", ",\n    \"warnings\" : []", "0,0,-100,0\n1,0.5,-200,0\n");
  write_run(dir + "/stiff", "stopped", ",\n    \"reason\" : \"Newton: the tangent is ill-conditioned\"", "0,0,-1,0\n");
  write_run(dir + "/soft", "finished", ",\n    \"warnings\" : [\"penetration unacceptable: 2e-3\"]",
            "0,0,-100,0\n1,0.5,-201,0.002\n");
  write_run(dir + "/reference-1", "finished", "", "0,0,-100,0\n1,0.5,-200.1,0\n");
  const auto result = [&](int i) { return evaluate_expectation(c, c.expectations[i], dir); };
  EXPECT_TRUE(result(1).pass) << result(1).message;
  const ExpectationResult soft = result(2);
  EXPECT_TRUE(soft.pass) << soft.message;
  ASSERT_EQ(soft.values.size(), 3u);
  EXPECT_NEAR(soft.values[0].value, 0.005, 1e-12);  // |201 - 200| / 200
  EXPECT_NEAR(soft.values[2].value, 0.002, 1e-12);
  const ExpectationResult own = result(0);
  EXPECT_TRUE(own.pass) << own.message;  // 5e-4 from ipopt, within 1e-3
  EXPECT_NEAR(own.values[0].value, 0.1 / 200.1, 1e-12);
  // Each way of failing.
  write_run(dir + "/case", "stopped", ",\n    \"warnings\" : []", "0,0,-100,0\n1,0.5,-200,0\n");
  EXPECT_NE(result(0).message.find("outcome stopped, expected finished"), std::string::npos);
  write_run(dir + "/case", "finished", ",\n    \"warnings\" : [\"penetration\"]", "0,0,-100,0\n1,0.5,-200,0\n");
  EXPECT_NE(result(0).message.find("unexpected warning: penetration"), std::string::npos);
  write_run(dir + "/case", "finished", ",\n    \"warnings\" : []", "0,0,-100,0\n1,0.5,-201,0\n");
  EXPECT_NE(result(0).message.find("expected in [-inf, 0.001]"), std::string::npos) << result(0).message;
  write_run(dir + "/stiff", "stopped", ",\n    \"reason\" : \"Newton: no convergence\"", "0,0,-1,0\n");
  EXPECT_NE(result(1).message.find("lacks 'ill-conditioned'"), std::string::npos);
  write_run(dir + "/soft", "finished", ",\n    \"warnings\" : []", "0,0,-100,0\n1,0.5,-201,0.002\n");
  EXPECT_NE(result(2).message.find("no warning contains 'penetration'"), std::string::npos);
}

TEST(Expectations, FindsNonFiniteNumbers) {
  const std::string dir = (fs::temp_directory_path() / "rpfem_unit_expect_nan").string();
  fs::remove_all(dir);
  write_run(dir, "finished", ",\n    \"x\" : 1e-05,\n    \"ok\" : true", "0,0,-100,0\n");
  EXPECT_EQ(non_finite_entries(dir), "");
  write_run(dir, "finished", ",\n    \"x\" : nan", "0,0,-100,0\n");
  EXPECT_NE(non_finite_entries(dir).find("summary.json: 'nan'"), std::string::npos);
  write_run(dir, "finished", "", "0,0,-nan,0\n");
  EXPECT_NE(non_finite_entries(dir).find("history.csv row 1"), std::string::npos);
  write_run(dir, "finished", "", "0,0,inf,0\n");
  EXPECT_NE(non_finite_entries(dir), "");
}
