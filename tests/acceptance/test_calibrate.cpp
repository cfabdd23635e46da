// `rpfem calibrate` (docs/calibrate.md): a target made by a run at a known
// friction value is recovered from another starting value, through a ring
// calibration table (friction factor m) and through a load-stroke table
// (Coulomb mu); --auto-beta finds the smallest penalty meeting a
// penetration tolerance. The ring to 20 % reduction on the half-divisions
// mesh: about 0.3 s a run (m), 0.6 s (mu).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/types.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

namespace {

const std::string kRing = "--set run.mesh_factor=0.5";

// Runs `rpfem calibrate` on a shipped case; expects exit code 0.
std::string calibrate(const std::string& name, const std::string& args) {
  const std::string out = accept::test_out_dir("_calibration");
  const std::string cmd = "calibrate " + std::string(RPFEM_SOURCE_DIR) + "/cases/" + name + ".toml --out " + out +
                          " --quiet " + args;
  EXPECT_EQ(accept::rpfem(cmd), 0) << cmd;
  return out;
}

// Every 4th step of a run's history (from step 4) as a target table.
std::string write_target(const std::string& dir, const std::string& header, const std::string& column,
                         double x_per_mm, double y_scale) {
  const History h = read_history(dir + "/history.csv");
  const std::string path = dir + "/target.csv";
  std::ofstream out(path);
  out << header << "\n";
  char line[96];
  for (std::size_t i = 4; i < h.rows(); i += 4) {
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", h.at("stroke")[i] * x_per_mm, h.at(column)[i] * y_scale);
    out << line;
  }
  return path;
}

struct Fit {
  double value = NAN, misfit = NAN, x0 = NAN, misfit_x0 = NAN;
  int simulations = 0;
  std::string best_dir;
};

// From OUT/evaluations.csv: the best row, and the first (x0).
Fit read_fit(const std::string& out, const std::string& score) {
  const History e = read_history(out + "/evaluations.csv");
  Fit f;
  f.simulations = static_cast<int>(e.rows());
  if (e.rows() == 0) return f;
  f.x0 = e.at("value").front(), f.misfit_x0 = e.at(score).front();
  for (std::size_t i = 0; i < e.rows(); ++i)
    if (e.at("best")[i] == 1) {
      f.value = e.at("value")[i], f.misfit = e.at(score)[i];
      char d[32];
      std::snprintf(d, sizeof d, "/evals/%03d", static_cast<int>(e.at("evaluation")[i]));
      f.best_dir = out + d;
    }
  return f;
}

// The fit within 0.01 of the value the target was made with, and the target
// sensitive to it: the misfit at x0 above `clearly`, at the fit below 1 % of
// that.
void expect_recovered(const Fit& f, const char* what, double truth, double clearly) {
  std::printf("[measured] %s = %g from x0 = %g: fitted %.7f, misfit %.3e (at x0 %.3e), %d simulations\n", what,
              truth, f.x0, f.value, f.misfit, f.misfit_x0, f.simulations);
  EXPECT_NEAR(f.value, truth, 0.01);
  EXPECT_GT(f.misfit_x0, clearly);
  EXPECT_LT(f.misfit, 1e-2 * f.misfit_x0);
}

bool finished(const std::string& out) {
  return read_text(out + "/calibration.json").find("\"status\" : \"finished\"") != std::string::npos;
}

}  // namespace

// Ring calibration table at m = 0.3 (friction factor), recovered from m = 0.1.
//~ feature = "studies"
//~ scene = "ring_compression at mesh factor 0.5 to 20 %: a target table made at m = 0.3, fitted from m = 0.1"
//~ source = "Male and Cockcroft 1964 (friction from the ring's inner diameter)"
//~ [[check]]
//~ what = "fitted m against the m that made the target"
//~ compares = "the same scene run otherwise"
//~ tolerance = "0.01"
//~ why = "the target is exact for m = 0.3 on this mesh; 0.01 of m is finer than a ring chart is read"
//~ [[check]]
//~ what = "misfit at x0 above 1 point; at the fit below 1 % of it"
//~ compares = "expected behaviour"
//~ tolerance = "> 1.0; < 1e-2 x"
//~ why = "the target must be sensitive to m, or a recovered value proves nothing"
TEST(Calibrate, RecoversFrictionFactorFromRingTable) {
  const std::string made =
      run_case("ring_compression", kRing + " --set stepping.end_stroke=2.0 --set dies.top_die.friction.m=0.3", 0,
               "_target");
  // The half model is 10 mm high: reduction = 100 stroke / 10 mm.
  const std::string target =
      write_target(made, "reduction_percent,inner_diameter_change_percent", "inner_diameter_mid", 10.0, 1.0);
  const std::string out =
      calibrate("ring_compression", kRing + " --target " + target +
                                        " --param dies.top_die.friction.m --bounds 0,1 --x0 0.1");
  const Fit f = read_fit(out, "misfit");
  EXPECT_TRUE(finished(out));
  expect_recovered(f, "ring table (misfit in percentage points), m", 0.3, 1.0);
  // Runs only to the target's last point (20 % of 10 mm).
  EXPECT_NEAR(read_history(f.best_dir + "/history.csv").at("stroke").back(), 2.0, 1e-9);
}

// Load-stroke table at Coulomb mu = 0.08, recovered from mu = 0.2.
//~ feature = "studies"
//~ scene = "ring_compression, Coulomb, mesh factor 0.5 to 20 %: a load-stroke target made at mu = 0.08, fitted from mu = 0.2"
//~ source = "paper eq. 10-12 (Coulomb friction)"
//~ [[check]]
//~ what = "fitted mu against the mu that made the target"
//~ compares = "the same scene run otherwise"
//~ tolerance = "0.01"
//~ why = "the target is exact for mu = 0.08 on this mesh; 0.01 of mu is finer than friction is known in practice"
//~ [[check]]
//~ what = "relative misfit at x0 above 0.03; at the fit below 1 % of it"
//~ compares = "expected behaviour"
//~ tolerance = "> 0.03; < 1e-2 x"
//~ why = "the load must be sensitive to mu, or a recovered value proves nothing"
TEST(Calibrate, RecoversCoulombFrictionFromLoadStrokeTable) {
  const std::string law = " --set dies.top_die.friction.law=coulomb";
  const std::string made =
      run_case("ring_compression", kRing + law + " --set stepping.end_stroke=2.0 --set dies.top_die.friction.mu=0.08",
               0, "_target");
  const std::string target = write_target(made, "stroke_mm,load_kN", "top_die.Fy", 1.0, -1e-3);
  const std::string out = calibrate("ring_compression", kRing + law + " --target " + target +
                                                             " --param dies.top_die.friction.mu --bounds 0,0.5 --x0 0.2");
  const Fit f = read_fit(out, "misfit");
  EXPECT_TRUE(finished(out));
  expect_recovered(f, "load-stroke table (relative misfit), mu", 0.08, 0.03);
}

// The smallest beta_factor meeting the tolerance: its run meets it, half of
// it does not.
//~ feature = "studies"
//~ scene = "upsetting_dies_frictionless_axisym, mesh factor 0.5, to 1 mm: --auto-beta 1e-4"
//~ source = "paper eq. 7-8 (the penalty's penetration falls as 1 / beta)"
//~ [[check]]
//~ what = "penetration at the beta found; at half of it"
//~ compares = "the same scene run otherwise"
//~ tolerance = "<= 1e-4 at the beta found; > 1e-4 at half"
//~ why = "the smallest beta meeting the tolerance: measured 9.9999e-5 at it, 2.0e-4 at half (first order in 1 / beta)"
TEST(Calibrate, AutoBetaFindsTheSmallestPenalty) {
  const double tol = 1e-4;
  const std::string scene = " --set run.mesh_factor=0.5 --set stepping.end_stroke=1.0";
  const std::string out = calibrate("upsetting_dies_frictionless_axisym", "--auto-beta 1e-4" + scene);
  const Fit f = read_fit(out, "max_penetration_rel");
  EXPECT_TRUE(finished(out));
  ASSERT_TRUE(std::isfinite(f.value));
  const auto largest = [](const std::string& dir) {
    const History h = read_history(dir + "/history.csv");  // owns the column
    const auto& p = h.at("max_penetration_rel");
    return *std::max_element(p.begin(), p.end());
  };
  const double found = largest(f.best_dir);
  char half[64];
  std::snprintf(half, sizeof half, "%.17g", f.value / 2);
  const std::string below = run_case("upsetting_dies_frictionless_axisym",
                                     "--formulation penalty" + scene + " --set formulations.penalty.beta_factor=" + half,
                                     0, "_half");
  const double at_half = largest(below);
  std::printf("[measured] auto-beta, tolerance %.0e: beta_factor %.4e, penetration %.4e; at half of it %.4e; "
              "at the default (1) %.4e; %d simulations\n",
              tol, f.value, found, at_half, f.misfit_x0, f.simulations);
  EXPECT_LE(found, tol);
  EXPECT_GT(at_half, tol);
}
