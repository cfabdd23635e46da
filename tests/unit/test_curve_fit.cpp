// Calibration targets (verification/curve_fit.*): reading both CSV tables,
// each kind of bad input named by file and line, and the misfit of known
// curves.
#include <gtest/gtest.h>

#include <cmath>

#include "core/types.hpp"
#include "curve_fit.hpp"
#include "temp_file.hpp"

using namespace rpfem;
using unit::write_temp;

namespace {

// The InputError message of reading text as a target file (empty if none).
std::string read_error(const std::string& name, const std::string& text) {
  const std::string path = write_temp(name, text);
  try {
    read_target_curve(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TargetCurve, ReadsBothTables) {
  const TargetCurve load = read_target_curve(write_temp("t_load.csv", "stroke_mm,load_kN\n0.5,100\n\n1.0, 150.5\r\n"));
  EXPECT_EQ(load.kind, TargetKind::LoadStroke);
  ASSERT_EQ(load.x.size(), 2u);
  EXPECT_EQ(load.x[1], 1.0);
  EXPECT_EQ(load.y[1], 150.5);
  EXPECT_EQ(load.line[1], 4);  // the blank line counted
  const TargetCurve ring = read_target_curve(
      write_temp("t_ring.csv", "reduction_percent, inner_diameter_change_percent\n10,-1.5\n20,-4\n30,-8.25\n"));
  EXPECT_EQ(ring.kind, TargetKind::Ring);
  EXPECT_EQ(ring.y, (std::vector<double>{-1.5, -4, -8.25}));
}

TEST(TargetCurve, BadInputNamesFileLineAndExpectation) {
  EXPECT_NE(read_error("t_none.csv", "").find("t_none.csv:1: expected the header 'stroke_mm,load_kN'"),
            std::string::npos);
  const std::string header = read_error("t_header.csv", "stroke,load\n1,2\n2,3\n");
  EXPECT_NE(header.find("t_header.csv:1: expected the header"), std::string::npos) << header;
  EXPECT_NE(header.find("got 'stroke,load'"), std::string::npos) << header;
  const std::string cell = read_error("t_cell.csv", "stroke_mm,load_kN\n1,2\n2,abc\n");
  EXPECT_NE(cell.find("t_cell.csv:3: column 2 (load_kN): expected a number, got 'abc'"), std::string::npos) << cell;
  const std::string empty = read_error("t_emptycell.csv", "stroke_mm,load_kN\n1,\n2,3\n");
  EXPECT_NE(empty.find("t_emptycell.csv:2: column 2 (load_kN): expected a number, got ''"), std::string::npos)
      << empty;
  const std::string cells = read_error("t_cells.csv", "stroke_mm,load_kN\n1,2,3\n2,3\n");
  EXPECT_NE(cells.find("t_cells.csv:2: expected 2 comma-separated numbers"), std::string::npos) << cells;
  const std::string rows = read_error("t_rows.csv", "stroke_mm,load_kN\n1,2\n");
  EXPECT_NE(rows.find("t_rows.csv: expected at least 2 data rows after the header, got 1"), std::string::npos)
      << rows;
  const std::string order = read_error("t_order.csv", "stroke_mm,load_kN\n1,2\n1,3\n");
  EXPECT_NE(order.find("t_order.csv:3: column 1 (stroke_mm): expected a value above the previous row's 1"),
            std::string::npos)
      << order;
  const std::string negative = read_error("t_neg.csv", "stroke_mm,load_kN\n-1,2\n1,3\n");
  EXPECT_NE(negative.find("t_neg.csv:2: column 1 (stroke_mm): expected a value >= 0"), std::string::npos) << negative;
  const std::string load = read_error("t_load0.csv", "stroke_mm,load_kN\n1,2\n2,0\n");
  EXPECT_NE(load.find("t_load0.csv:3: column 2 (load_kN): expected a positive load"), std::string::npos) << load;
  const std::string reduction =
      read_error("t_red.csv", "reduction_percent,inner_diameter_change_percent\n10,1\n100,2\n");
  EXPECT_NE(reduction.find("t_red.csv:3: column 1 (reduction_percent): expected a reduction below 100 %"),
            std::string::npos)
      << reduction;
  try {
    read_target_curve("/nonexistent/target.csv");
    ADD_FAILURE() << "a missing file was read";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/target.csv: no such target file");
  }
}

TEST(TargetCurve, PointsBeyondTheSimulatedRangeNameTheirLine) {
  const TargetCurve t = read_target_curve(write_temp("t_range.csv", "stroke_mm,load_kN\n1,2\n2,3\n6,4\n"));
  EXPECT_NO_THROW(require_within(t, 6.0, "the case's end stroke"));
  try {
    require_within(t, 5.0, "the case's stepping.end_stroke = 5 mm");
    ADD_FAILURE() << "a point beyond the range passed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t_range.csv:4: column 1 (stroke_mm): 6 is beyond the simulated range, the "
                                         "case's stepping.end_stroke = 5 mm"),
              std::string::npos)
        << e.what();
  }
}

TEST(TargetMisfit, KnownValuesForExactScaledAndShiftedCurves) {
  TargetCurve load;
  load.kind = TargetKind::LoadStroke;
  load.x = {1, 2, 3};
  load.y = {10, 20, 30};
  // The simulation at other strokes, linear: exact at the target's points.
  const std::vector<double> s{0, 0.5, 1.5, 2.5, 3.5}, F{0, 5, 15, 25, 35};
  EXPECT_NEAR(target_misfit(load, s, F), 0.0, 1e-15);
  // 3 % high everywhere: the relative RMS is 0.03.
  std::vector<double> high = F;
  for (double& v : high) v *= 1.03;
  EXPECT_NEAR(target_misfit(load, s, high), 0.03, 1e-14);
  // Shifted by 1 kN: relative differences 1/10, 1/20, 1/30.
  std::vector<double> shifted = F;
  for (double& v : shifted) v += 1;
  EXPECT_NEAR(target_misfit(load, s, shifted), std::sqrt((0.01 + 0.0025 + 1.0 / 900) / 3), 1e-14);

  TargetCurve ring;
  ring.kind = TargetKind::Ring;
  ring.x = {10, 20};
  ring.y = {-1, -3};
  // d(r) = -r / 10 + 0.5: differences 0.5 and 1.5 percentage points.
  EXPECT_NEAR(target_misfit(ring, {0, 30}, {0.5, -2.5}), std::sqrt((0.25 + 2.25) / 2), 1e-14);
  // A simulation that stops before the target's last point is refused.
  EXPECT_THROW(target_misfit(ring, {0, 15}, {0, -1}), std::invalid_argument);
}
