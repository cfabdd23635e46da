// What a sweep measures (verification/sweep_metrics.*) and its table
// (io/table_writer.*): Richardson's estimate on a known expansion, the
// per-run metrics of a small history, the load and monitor errors against
// a reference, the mean load over a stroke, the observed order of errors
// of a known order as a regularization parameter falls, and the table read
// back from CSV and HDF5.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/table_writer.hpp"
#include "results.hpp"
#include "sweep_metrics.hpp"

using namespace rpfem;

TEST(Richardson, RecoversOrderAndLimitOfAKnownExpansion) {
  // f(h) = 10 + 3 h^2, sizes given out of order, a coarser fourth ignored.
  auto f = [](double h) { return 10 + 3 * h * h; };
  const Richardson r = richardson({1.0, 0.25, 2.0, 0.5}, {f(1.0), f(0.25), f(2.0) + 1, f(0.5)});
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_NEAR(r.order, 2.0, 1e-12);
  EXPECT_NEAR(r.extrapolated, 10.0, 1e-12);
  EXPECT_DOUBLE_EQ(r.ratio, 2.0);
}

TEST(Richardson, RefusesWhatItCannotEstimate) {
  EXPECT_FALSE(richardson({1, 0.5}, {1, 2}).ok);                // two values
  EXPECT_FALSE(richardson({1, 0.5, 0.2}, {3, 2, 1.5}).ok);      // ratios 2 and 2.5
  EXPECT_FALSE(richardson({1, 0.5, 0.25}, {3, 2, 1}).ok);       // differences not shrinking
  EXPECT_FALSE(richardson({1, 0.5, 0.25}, {3, 2, 2.5}).ok);     // oscillating
}

namespace {
History history(const std::vector<double>& stroke, const std::vector<double>& load,
                const std::vector<double>& iterations) {
  History h;
  h.columns = {"stroke", "F", "newton_iterations", "volume_change", "max_penetration_rel", "tangent_rcond"};
  h.data["stroke"] = stroke;
  h.data["F"] = load;
  h.data["newton_iterations"] = iterations;
  h.data["volume_change"] = std::vector<double>(stroke.size(), 0.0);
  h.data["volume_change"].back() = -2e-6;
  h.data["max_penetration_rel"] = std::vector<double>(stroke.size(), 1e-4);
  h.data["max_penetration_rel"][1] = 3e-4;
  h.data["tangent_rcond"] = std::vector<double>(stroke.size(), 1e-6);
  h.data["tangent_rcond"][2] = -1;                                   // a step that factorized nothing
  if (stroke.size() > 3) h.data["tangent_rcond"][3] = 2e-9;
  return h;
}
}  // namespace

TEST(SweepMetrics, PerRunValuesFromTheHistory) {
  const History h = history({0, 1, 2, 3, 4}, {0, -1000, -2000, -3000, -4500}, {30, 4, 9, 5, 20});
  const RunMetrics m = run_metrics(h, "F");
  EXPECT_EQ(m.steps, 4);
  EXPECT_DOUBLE_EQ(m.final_stroke, 4.0);
  EXPECT_DOUBLE_EQ(m.final_load, 4.5);  // kN
  EXPECT_DOUBLE_EQ(m.penetration, 3e-4);
  EXPECT_DOUBLE_EQ(m.volume_error, 2e-6);
  EXPECT_DOUBLE_EQ(m.iterations_mean, 9.5);   // step 0's cold start left out
  EXPECT_DOUBLE_EQ(m.iterations_median, 7.0);
  EXPECT_DOUBLE_EQ(m.iterations_max, 20.0);
  EXPECT_DOUBLE_EQ(m.rcond, 2e-9);
  EXPECT_DOUBLE_EQ(m.iterations_per_solve_median, -1.0);  // no solves column
  History s = h;
  s.columns.push_back("solves");
  s.data["solves"] = {3, 2, 3, 1, 2};  // per step: 2, 3, 5, 10 iterations per solve
  EXPECT_DOUBLE_EQ(run_metrics(s, "F").iterations_per_solve_median, 4.0);
}

TEST(SweepMetrics, LoadErrorAgainstAReferenceFromAStroke) {
  const History ref = history({0, 1, 2, 3, 4}, {0, -1000, -2000, -3000, -4000}, {1, 1, 1, 1, 1});
  const History run = history({0, 2, 4}, {0, -2100, -4040}, {1, 1, 1});
  const LoadError all = load_error(run, ref, "F", 0.0), late = load_error(run, ref, "F", 3.0);
  EXPECT_NEAR(all.largest, 0.05, 1e-12);
  EXPECT_NEAR(late.largest, 0.01, 1e-12);
  EXPECT_NEAR(all.final, 0.01, 1e-12);
}

TEST(SweepMetrics, MeanLoadIsTheWorkOverTheStrokeFromAStroke) {
  // |F| = 1000 s N (kN: s) to 2 mm, then a landing: a jump to 3 kN held to 4 mm.
  const History h = history({0, 1, 2, 2.0001, 3, 4}, {0, -1000, -2000, -3000, -3000, -3000}, {1, 1, 1, 1, 1, 1});
  const double landing = 0.5 * (2 + 3) * 1e-4;  // kN mm, the jump's interval
  EXPECT_NEAR(mean_load(h, "F", 0.0), (2 + landing + 3 * 1.9999) / 4, 1e-12);
  // From 1.5 mm: the first interval cut there (|F| 1.5 kN).
  EXPECT_NEAR(mean_load(h, "F", 1.5), (0.5 * (1.5 + 2) * 0.5 + landing + 3 * 1.9999) / 2.5, 1e-12);
  EXPECT_EQ(mean_load(h, "F", 4.0), -1.0);  // nothing past the last stroke
}

TEST(SweepMetrics, MonitorDifferenceInItsOwnUnitAtTheRunsStrokes) {
  // A monitor in % against the reference's, interpolated at the run's strokes.
  History ref = history({0, 1, 2, 3, 4}, {0, -1, -2, -3, -4}, {1, 1, 1, 1, 1});
  ref.data["d"] = {0, -10, -20, -30, -40};
  History run = history({0, 1.5, 4}, {0, -1.5, -4}, {1, 1, 1});
  run.data["d"] = {0, -15.5, -40.25};
  const LoadError all = column_difference(run, ref, "d", 0.0), late = column_difference(run, ref, "d", 2.0);
  EXPECT_NEAR(all.largest, 0.5, 1e-12);  // percentage points, at 1.5 mm
  EXPECT_NEAR(late.largest, 0.25, 1e-12);
  EXPECT_NEAR(all.final, 0.25, 1e-12);
  // A run past the reference's last stroke: its last stroke is not compared.
  History longer = run;
  longer.data["stroke"].back() = 5.0;
  EXPECT_EQ(column_difference(longer, ref, "d", 0.0).final, -1.0);
}

TEST(SweepMetrics, MeanLoadErrorOverTheRunsStrokes) {
  // The reference |F| = s kN; the run's 1 % above it: the mean loads too.
  const History ref = history({0, 1, 2, 3, 4}, {0, -1000, -2000, -3000, -4000}, {1, 1, 1, 1, 1});
  const History run = history({0, 0.5, 2.5}, {0, -505, -2525}, {1, 1, 1});
  // The reference cut at 2.5 mm (interpolated there), not its mean to 4 mm.
  EXPECT_NEAR(mean_load_error(run, ref, "F", 0.0), 0.01, 1e-12);
  EXPECT_NEAR(mean_load_error(run, ref, "F", 1.0), 0.01, 1e-12);
  History longer = run;
  longer.data["stroke"].back() = 4.5;  // past the reference: not measured
  EXPECT_EQ(mean_load_error(longer, ref, "F", 0.0), -1.0);
}

TEST(ObservedOrders, RecoverAKnownOrderAboveTheFloor) {
  // e = 3 a^0.7 down to a floor of round-off at 1e-9 (e = 1e-10 and 0
  // below it), values out of order, one not measured (-1).
  const std::vector<double> a{1e-3, 1e-1, 1e-5, 1e-2, 1e-4, 1e-7, 1e-6, 1e-8};
  std::vector<double> e;
  for (double x : a) e.push_back(3 * std::pow(x, 0.7));
  e[5] = 1e-10, e[6] = -1, e[7] = 0;
  const ObservedOrders o = observed_orders(a, e, 1e-9);
  ASSERT_EQ(o.a.size(), 8u);
  EXPECT_EQ(o.a.front(), 1e-1);  // falling
  EXPECT_EQ(o.a.back(), 1e-8);
  ASSERT_EQ(o.successive.size(), 7u);
  for (int k = 0; k < 4; ++k) {  // 1e-1 to 1e-5
    EXPECT_TRUE(o.successive_measured[k]) << k;
    EXPECT_NEAR(o.successive[k], 0.7, 1e-12) << k;
  }
  for (int k = 4; k < 7; ++k) EXPECT_FALSE(o.successive_measured[k]) << k;  // 1e-6 not measured, 1e-7 at the floor
  EXPECT_EQ(o.fit_points, 5);
  EXPECT_NEAR(o.fit, 0.7, 1e-12);
}

TEST(ObservedOrders, LeastSquaresThroughScatterAndTooFewPoints) {
  // Errors 2 a (order 1) times 1.1, 1/1.1 by turns: the successive slopes
  // scatter about 1 by 2 log10 1.1, the fit over the whole range does not.
  const std::vector<double> a{1, 0.1, 0.01, 1e-3, 1e-4};
  std::vector<double> e;
  for (std::size_t k = 0; k < a.size(); ++k) e.push_back(2 * a[k] * (k % 2 ? 1 / 1.1 : 1.1));
  const ObservedOrders o = observed_orders(a, e, 0.0);
  EXPECT_NEAR(o.successive[0], 1 + 2 * std::log10(1.1), 1e-12);
  EXPECT_NEAR(o.successive[1], 1 - 2 * std::log10(1.1), 1e-12);
  EXPECT_EQ(o.fit_points, 5);
  // The scatter r = +-ln 1.1 is symmetric about the middle value: the
  // slope's shift sum (x - xm) r / sum (x - xm)^2 (x = ln a) is zero.
  EXPECT_NEAR(o.fit, 1.0, 1e-12);
  // Only the smallest value's error 1.1 times the line: x - xm = -2 ln 10
  // there, sum (x - xm)^2 = 10 (ln 10)^2, so the slope is 1 - 0.2 log10 1.1.
  e = {2 * a[0], 2 * a[1], 2 * a[2], 2 * a[3], 2.2 * a[4]};
  EXPECT_NEAR(observed_orders(a, e, 0.0).fit, 1 - 0.2 * std::log10(1.1), 1e-12);
  // An error that grows as a falls: a negative order, measured as such.
  EXPECT_NEAR(observed_orders({1e-2, 1e-3}, {1e-4, 1e-3}, 0.0).successive[0], -1.0, 1e-12);
  // One value above the floor: no fit.
  const ObservedOrders one = observed_orders({1e-1, 1e-2}, {1e-3, 1e-7}, 1e-6);
  EXPECT_FALSE(one.fit_measured());
  EXPECT_FALSE(one.successive_measured[0]);
}

TEST(TableWriter, CsvAndHdf5HoldTheSameRows) {
  Table t;
  t.columns = {"run", "formulation", "beta"};
  t.add_row({{"run", 0}, {"beta", 1e-2}}, {{"formulation", "penalty"}});
  t.add_row({{"run", 1}, {"beta", 1e12}}, {{"formulation", "ipopt"}});
  EXPECT_EQ(t.rows(), 2u);
  EXPECT_THROW(t.add_row({{"run", 2}, {"beta", NAN}}, {{"formulation", "x"}}), std::logic_error);
  EXPECT_THROW(t.add_row({{"run", 2}}, {{"formulation", "x"}}), std::logic_error);
  const auto dir = std::filesystem::temp_directory_path() / "rpfem_table_test";
  std::filesystem::create_directories(dir);
  write_table_csv((dir / "t.csv").string(), t);
  write_table_h5((dir / "t.h5").string(), t, "{\"study\": \"x\"}");
  EXPECT_EQ(read_text((dir / "t.csv").string()), "run,formulation,beta\n0,penalty,0.01\n1,ipopt,1e+12\n");
  const auto beta = read_h5_dataset((dir / "t.h5").string(), "/table/beta");
  ASSERT_EQ(beta.size(), 2u);
  EXPECT_DOUBLE_EQ(beta[1], 1e12);
}

// A study's metadata JSON grows with its runs (every run's overrides): 500
// runs made it larger than the 64 kB an attribute in its object's header
// can hold. Written at 1 MB and read back whole, beside a column list
// larger than 64 kB.
TEST(TableWriter, MetadataAndColumnsBeyond64kBAreWrittenAndReadBack) {
  Table t;
  std::string order;
  for (int c = 0; c < 3000; ++c) {
    t.columns.push_back("a_long_column_name_of_thirty_" + std::to_string(c));
    order += (c ? "," : "") + t.columns.back();
  }
  std::map<std::string, double> row;
  for (const auto& c : t.columns) row[c] = 1.0;
  t.add_row(row, {});
  std::string json = "{\"runs\": [";
  for (int r = 0; json.size() < (1u << 20); ++r) json += (r ? ", " : "") + std::string("{\"run\": ") + std::to_string(r) + "}";
  json += "]}";
  ASSERT_GT(order.size(), 65536u);
  const auto dir = std::filesystem::temp_directory_path() / "rpfem_table_large_test";
  std::filesystem::create_directories(dir);
  const std::string h5 = (dir / "t.h5").string();
  write_table_h5(h5, t, json);
  EXPECT_EQ(read_h5_text_attribute(h5, "/table", "metadata"), json);
  EXPECT_EQ(read_h5_text_attribute(h5, "/table", "columns"), order);
  EXPECT_EQ(read_h5_dataset(h5, "/table/" + t.columns.back()).size(), 1u);
}

// What a tolerance bounds (docs/theory.md, "Step control by a local error
// estimate"): max |F_h - F| over max |F|, the reference interpolated, no
// stroke within one step of either run's landing compared.
TEST(SweepMetrics, MaxRelativeLoadErrorLeavesTheLandingsOut) {
  History ref, run;
  ref.data["stroke"] = {0, 1, 2, 3, 4, 5, 6};
  ref.data["F"] = {0, -100, -200, -300, -400, -500, -600};
  run.data["stroke"] = {0, 0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6};
  //                       ref 50, 150, 250, 350, 450, 550, 600
  run.data["F"] = {0, -51, -150, -250, -350, -450, -553, -600};
  // No landings: the worst is 3 at 5.5 mm over the largest 600.
  EXPECT_NEAR(max_relative_load_error(run, ref, "F"), 3.0 / 600, 1e-15);
  // The run lands a node at 5.5 mm: strokes whose steps reach 4.5 to 6 mm
  // are left out (3.5 to 6 mm); the worst is then 1 at 0.5 mm.
  run.data["contact_nodes"] = {1, 1, 1, 1, 1, 1, 2, 2};
  EXPECT_NEAR(max_relative_load_error(run, ref, "F"), 1.0 / 600, 1e-15);
  EXPECT_EQ(landing_steps(run), std::vector<std::size_t>{6});
  // The reference lands at 6 mm instead (its window 5 to 6 mm): the same strokes out.
  run.data.erase("contact_nodes");
  ref.data["contact_nodes"] = {1, 1, 1, 1, 1, 1, 2};
  EXPECT_NEAR(max_relative_load_error(run, ref, "F"), 1.0 / 600, 1e-15);
  // And at 1 mm too (0 to 2 mm): only 3.5 mm is compared, where the loads agree.
  ref.data["contact_nodes"] = {1, 2, 2, 2, 2, 2, 3};
  EXPECT_EQ(max_relative_load_error(run, ref, "F"), 0.0);
  // A reference with no landing, a run landing at every step: nothing is compared.
  ref.data.erase("contact_nodes");
  run.data["contact_nodes"] = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(max_relative_load_error(run, ref, "F"), -1.0);
  EXPECT_EQ(max_relative_load_error(History{}, ref, "F"), -1.0);
}
