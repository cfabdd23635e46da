// The extreme scenes (cases/extremes/*.toml): each case states
// its expected outcome in [expect] tables (its own run and its variants');
// this runs every run the expectations need, asserts that no run crashed
// (exit 0 finished or 3 stopped, as its summary says), that none wrote a
// non-finite number, and that each expectation holds
// (verification/expectations.hpp). One test per case file, so ctest runs
// them in parallel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "expectations.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> extreme_cases() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(std::string(RPFEM_SOURCE_DIR) + "/cases/extremes"))
    if (e.path().extension() == ".toml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs one of the plan's runs into dir; returns the exit code (-1: killed).
int run(const ExpectedRun& r, const std::string& dir) {
  std::string args = "run";
  for (const auto& a : r.arguments()) args.append(" ").append(quoted(a));
  return accept::rpfem(args + " --out " + quoted(dir), quoted(dir + ".log"));
}

// What the report needs of each run: outcome, steps, iterations, the least
// tangent rcond, the largest penetration and volume change, time.
void print_run(const std::string& name, const std::string& dir) {
  const History h = read_history(dir + "/history.csv");
  double its = 0, pen = -1, dv = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    its = std::max(its, h.at("newton_iterations")[i]);
    dv = std::max(dv, std::abs(h.at("volume_change")[i]));
    if (h.data.count("max_penetration_rel")) pen = std::max(pen, h.at("max_penetration_rel")[i]);
  }
  const Summary s(dir);
  std::printf("[measured] %s: %s, %d steps to %.3g mm, %g Newton iterations (at most %g per step), "
              "min rcond %.2g, max penetration / h %.2g, max |volume change| %.2g, %.2f s\n",
              name.c_str(), s.string("status").value_or("?").c_str(), static_cast<int>(s.number("steps").value_or(-1)),
              s.number("final_stroke_mm").value_or(0), s.number("total_newton_iterations").value_or(0), its,
              s.number("min_tangent_rcond").value_or(-1), pen, dv, s.number("wall_time_s").value_or(0));
  if (const auto reason = s.string("reason")) std::printf("[measured]   reason: %s\n", reason->c_str());
  for (const auto& w : s.strings("warnings")) std::printf("[measured]   warning: %s\n", w.c_str());
}

class Extremes : public ::testing::TestWithParam<std::string> {};

}  // namespace

//~ feature = "extremes"
//~ scene = "every case of cases/extremes, its runs and variants (one ctest entry per case)"
//~ source = "each case's [expect] tables (verification/expectations.hpp)"
//~ [[check]]
//~ what = "each run: exit 0 and finished, or exit 3 and stopped; no non-finite number in its output"
//~ compares = "expected behaviour"
//~ tolerance = "exit 0 or 3"
//~ why = "an extreme may stop, but never crash, fail as bad input, or write NaN"
//~ [[check]]
//~ what = "each expectation of the case (outcome, bounds on measured values)"
//~ compares = "expected behaviour"
//~ tolerance = "as the case states"
//~ why = "the tolerance and its reason sit in the case file beside the scene they describe"
TEST_P(Extremes, EndAsTheirCasesSay) {
  const ExpectedCase c = read_expected_case(GetParam());
  const std::string scene = fs::path(GetParam()).stem().string();
  const std::string out = (fs::temp_directory_path() / ("rpfem_extremes_" + scene)).string();
  fs::remove_all(out);
  fs::create_directories(out);
  for (const ExpectedRun& r : c.runs) {
    const std::string dir = out + "/" + r.label;
    const int rc = run(r, dir);
    const std::string status = summary_string(dir, "status").value_or("none");
    // Never a crash or bad input: finished (0) or stopped with a reason (3).
    EXPECT_TRUE((rc == 0 && status == "finished") || (rc == 3 && status == "stopped"))
        << r.label << ": exit code " << rc << ", status " << status << " (log " << dir << ".log)";
    EXPECT_EQ(non_finite_entries(dir), "") << r.label;
    print_run(scene + " " + r.label, dir);
  }
  for (const Expectation& e : c.expectations) {
    const ExpectationResult r = evaluate_expectation(c, e, out);
    EXPECT_TRUE(r.pass) << scene << " " << r.run << ": " << r.message;
    for (const MeasuredValue& v : r.values)
      std::printf("[measured] %s %s: %s = %.3e%s\n", scene.c_str(), r.run.c_str(), v.name.c_str(), v.value,
                  v.pass ? "" : " (out of bounds)");
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Extremes, ::testing::ValuesIn(extreme_cases()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           std::string n = fs::path(i.param).stem().string();
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });
