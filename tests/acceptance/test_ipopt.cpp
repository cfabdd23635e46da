// The ipopt formulation (formulations/ipopt): a block on a flat die with an
// analytic multiplier, a constraint that must stay inactive, an infeasible
// configuration that must be reported; frictionless flat-die upsetting
// against the exact load and `direct`; Test I's two spheres against the
// penalty solution (the Kuhn-Tucker residuals checked at every step).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analytic.hpp"
#include "core/types.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;
using accept::test_out_dir;

namespace {

// One plane-strain element, 1 x 1 mm, perfectly plastic (K = 100 MPa),
// x = 0 a symmetry plane, pressed down at 1 mm/s on a fixed frictionless
// floor die; a wall die touching its right side moves away at 10 mm/s.
// Exact: sigma_yy = -(2 / sqrt 3) K everywhere, so each floor node carries
// (2 / sqrt 3) K (1/2) N per mm of depth: the multiplier of its row.
const char* kBlock = R"(
[run]
name = "ipopt_block"
geometry = "plane_strain"
formulation = "ipopt"
[bodies.block.material]
K = 100.0
n = 0.0
[bodies.block.mesh]
shape = "rectangle"
width = 1.0
height = 1.0
nx = 1
ny = 1
[[bodies.block.velocity]]
name = "top"
side = "top"
vy = -1.0
[[symmetry]]
normal = "x"
[dies.floor]
[[dies.floor.vertex]]
x = 3.0
y = 0.0
[[dies.floor.vertex]]
x = -1.0
y = 0.0
[dies.wall]
vx = 10.0
[[dies.wall.vertex]]
x = 1.0
y = 3.0
[[dies.wall.vertex]]
x = 1.0
y = -1.0
[[contact_pairs]]
body = "block"
sides = "bottom"
die = "floor"
[[contact_pairs]]
body = "block"
sides = "right"
die = "wall"
[stepping]
reference = "top"
end_stroke = 0.1
stroke_increment = 0.05
output_every = 1
)";

std::string write_case(const std::string& dir, const std::string& text) {
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/case.toml";
  std::ofstream(path) << text;
  return path;
}

int run(const std::string& case_path, const std::string& out, const std::string& extra, std::string* log = nullptr) {
  return accept::rpfem("run " + case_path + " --out " + out + " --quiet " + extra, out + ".log", log);
}

}  // namespace

//~ feature = "ipopt"
//~ scene = "one plane-strain element, perfectly plastic (K = 100 MPa), on a floor die, a wall die receding"
//~ source = "homogeneous plane-strain compression: sigma_yy = -(2 / sqrt 3) K, each floor node carries (2 / sqrt 3) K times its lumped length (Kobayashi, Oh and Altan 1989, sec. 5.2)"
//~ [[check]]
//~ what = "every floor node's multiplier (contact pressure), every recorded step"
//~ compares = "exact solution"
//~ tolerance = "1e-6 (relative)"
//~ why = "the multiplier is the exact nodal force of a uniform stress; 1e-6 is Ipopt's convergence with margin"
//~ [[check]]
//~ what = "floor load = 2 w sigma_yy (whole model); top load equals minus the floor's"
//~ compares = "conservation"
//~ tolerance = "1e-6 of the exact load"
//~ why = "equilibrium of the block to the solver's precision"
//~ [[check]]
//~ what = "the receding wall's force"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-9 of the load"
//~ why = "a separating row carries nothing (complementarity): only round-off"
//~ [[check]]
//~ what = "kkt_primal, kkt_complementarity, kkt_stationarity at every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-9 (primal), 1e-8 (others)"
//~ why = "the exact enforcement's targets (see the section's introduction)"
TEST(Ipopt, FloorMultipliersAreTheExactNodalForcesAndTheRecedingWallCarriesNothing) {
  const std::string dir = test_out_dir();
  ASSERT_EQ(run(write_case(dir, kBlock), dir + "/out", ""), 0);
  const History h = read_history(dir + "/out/history.csv");
  const double exact = 2.0 / std::sqrt(3.0) * 100.0;  // MPa, N per mm of depth over 1 mm
  for (int k : read_h5_steps(dir + "/out/result.h5")) {
    char g[64];
    std::snprintf(g, sizeof g, "/steps/%06d/", k);
    const auto x = read_h5_dataset(dir + "/out/result.h5", std::string(g) + "coordinates");
    const auto p = read_h5_dataset(dir + "/out/result.h5", std::string(g) + "node/contact_pressure");
    double width = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      width = std::max(width, x[2 * i]);
      if (std::abs(x[2 * i + 1]) < 1e-12) EXPECT_NEAR(p[i], exact, 1e-6 * exact) << "floor node " << i;
    }
    // Whole model (mirrored at x = 0): 2 w sigma_yy per mm of depth.
    ASSERT_EQ(h.at("step")[k], k);
    EXPECT_NEAR(h.at("floor.Fy")[k], 2 * exact * width, 1e-6 * exact);
  }
  for (std::size_t i = 0; i < h.rows(); ++i) {
    const double load = h.at("floor.Fy")[i];
    EXPECT_EQ(h.at("contact_candidates")[i], 4);  // 2 floor, 2 wall rows
    EXPECT_EQ(h.at("contact_nodes")[i], 2);       // pressing: the floor's
    EXPECT_NEAR(h.at("top.Fy")[i], -load, 1e-6 * exact);
    EXPECT_LT(std::abs(h.at("wall.Fx")[i]), 1e-9 * load);  // the receding wall: inactive
    EXPECT_LT(h.at("kkt_primal")[i], 1e-9);
    EXPECT_LT(h.at("kkt_complementarity")[i], 1e-8);
    EXPECT_LT(h.at("kkt_stationarity")[i], 1e-8);
  }
}

//~ feature = "ipopt"
//~ scene = "the same block with a ceiling die closing onto a floor node"
//~ source = "Waechter and Biegler 2006 (Ipopt's infeasibility detection)"
//~ [[check]]
//~ what = "exit code 3, the log naming Ipopt and the infeasibility, no NaN in history.csv"
//~ compares = "expected behaviour"
//~ tolerance = "exit 3"
//~ why = "a node that must move up and down at once has no solution: the run stops saying why, and writes no NaN"
TEST(Ipopt, ContradictoryContactsAreReportedAsInfeasible) {
  // A ceiling die over the bottom-right node, moving down onto the floor:
  // that node must move up (floor) and down (ceiling) at once.
  std::string text = kBlock;
  text += R"(
[dies.ceiling]
vy = -1.0
[[dies.ceiling.vertex]]
x = 0.5
y = 0.0
[[dies.ceiling.vertex]]
x = 3.0
y = 0.0
[[contact_pairs]]
body = "block"
sides = "bottom"
die = "ceiling"
)";
  const std::string dir = test_out_dir();
  std::string log;
  EXPECT_EQ(run(write_case(dir, text), dir + "/out", "", &log), 3);
  EXPECT_NE(log.find("Ipopt"), std::string::npos) << log;
  EXPECT_NE(log.find("infeasib"), std::string::npos) << log;
  std::ifstream hist(dir + "/out/history.csv");
  std::stringstream ss;
  ss << hist.rdbuf();
  EXPECT_EQ(ss.str().find("nan"), std::string::npos);
}

//~ feature = "ipopt"
//~ scene = "upsetting_dies_frictionless_axisym under ipopt and direct"
//~ source = "Kobayashi, Oh and Altan 1989, sec. 5.2 (the exact load)"
//~ [[check]]
//~ what = "die load against the exact load, every step"
//~ compares = "exact solution"
//~ tolerance = "5e-3 (relative)"
//~ why = "measured 1.3e-5; the kernel's tolerance for homogeneous upsetting"
//~ [[check]]
//~ what = "die load against direct's, every step"
//~ compares = "another formulation"
//~ tolerance = "1e-3 (relative)"
//~ why = "both solve the same discrete Kuhn-Tucker problem (measured 5.3e-10); 1e-3 catches a row lost or pressing the wrong way"
//~ [[check]]
//~ what = "kkt_primal (penetration / h), every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-9"
//~ why = "an exact enforcement meets its gap to solver precision: Newton's velocity tolerance leaves about 1e-9 of h over a step"
//~ [[check]]
//~ what = "the other Kuhn-Tucker residuals (dual, complementarity, stationarity), every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8"
//~ why = "two decades above Ipopt's own tol (1e-10 of its scaled NLP error), whose scale can be larger than the checked measure's"
TEST(Ipopt, FlatDieUpsettingMatchesExactLoadAndDirect) {
  const std::string ip = run_case("upsetting_dies_frictionless_axisym", "--formulation ipopt", 0, "_ipopt");
  const std::string dir = run_case("upsetting_dies_frictionless_axisym", "--formulation direct", 0, "_direct");
  const History hi = read_history(ip + "/history.csv"), hd = read_history(dir + "/history.csv");
  ASSERT_EQ(hi.rows(), hd.rows());
  const FlowStressLaw l = accept::aisi1035();
  double exact = 0, direct = 0, kkt = 0, pen = 0;
  for (std::size_t i = 0; i < hi.rows(); ++i) {
    const double H = 20.0 - 2 * hi.at("stroke")[i];
    const double F = -hi.at("top_die.Fy")[i];
    exact = std::max(exact, std::abs(F / upsetting_load_axisymmetric(l, 20, 20, H) - 1));
    direct = std::max(direct, std::abs(F / -hd.at("top_die.Fy")[i] - 1));
    pen = std::max(pen, hi.at("kkt_primal")[i]);
    kkt = std::max({kkt, hi.at("kkt_dual")[i], hi.at("kkt_complementarity")[i], hi.at("kkt_stationarity")[i]});
  }
  EXPECT_NEAR(hi.at("stroke").back(), 5.0, 1e-9);
  EXPECT_LT(exact, 5e-3);
  EXPECT_LT(direct, 1e-3);
  EXPECT_LT(pen, 1e-9);
  EXPECT_LT(kkt, 1e-8);
  std::printf("[measured] ipopt vs exact %.3e, vs direct %.3e; penetration / element size %.2e, worst other "
              "Kuhn-Tucker residual %.2e\n",
              exact, direct, pen, kkt);
}

// Test I's two spheres (both meshed) to 0.5 mm: the same loads as the
// penalty formulation's two-pass solution, which follows the single-action
// sphere to 1e-6 (test_penalty.cpp).
//~ feature = "ipopt"
//~ scene = "paper_test1_double_action to 0.5 mm, ipopt against penalty two-pass"
//~ source = "paper Test I (Fig. 5-7); paper eq. 7-8 (the penalty, which converges to the exact solution)"
//~ [[check]]
//~ what = "top punch load against penalty's, every step"
//~ compares = "another formulation"
//~ tolerance = "1e-5 (relative)"
//~ why = "penalty converges to ipopt at first order in 1 / beta: measured 2.9e-7 at the default beta"
//~ [[check]]
//~ what = "kkt_primal (penetration / h), every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-9"
//~ why = "an exact enforcement meets its gap to solver precision: Newton's velocity tolerance leaves about 1e-9 of h over a step"
//~ [[check]]
//~ what = "the other Kuhn-Tucker residuals (dual, complementarity, stationarity), every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8"
//~ why = "two decades above Ipopt's own tol (1e-10 of its scaled NLP error), whose scale can be larger than the checked measure's"
TEST(Ipopt, TwoSpheresFollowThePenaltySolution) {
  const std::string set = "--set stepping.end_stroke=0.5";
  const std::string ip = run_case("paper_test1_double_action", "--formulation ipopt " + set, 0, "_ipopt");
  const std::string pe = run_case("paper_test1_double_action", set, 0, "_penalty");
  const History hi = read_history(ip + "/history.csv"), hp = read_history(pe + "/history.csv");
  ASSERT_EQ(hi.rows(), hp.rows());
  double load = 0, pen = 0, kkt = 0;
  for (std::size_t i = 0; i < hi.rows(); ++i) {
    load = std::max(load, std::abs(hi.at("top_punch.Fy")[i] / hp.at("top_punch.Fy")[i] - 1));
    pen = std::max(pen, hi.at("kkt_primal")[i]);
    kkt = std::max({kkt, hi.at("kkt_dual")[i], hi.at("kkt_complementarity")[i], hi.at("kkt_stationarity")[i]});
  }
  EXPECT_LT(load, 1e-5);
  EXPECT_LT(pen, 1e-9);
  EXPECT_LT(kkt, 1e-8);
  std::printf("[measured] Test I to 0.5 mm, ipopt vs penalty load %.2e; penetration / element size %.2e, worst "
              "other Kuhn-Tucker residual %.2e\n",
              load, pen, kkt);
}

// Die friction in the ipopt formulation: the arctan potential in the
// objective with its bound fixed per solve, updated from the multipliers
// (friction factor m = 0.1; Coulomb mu = 0.1 by the fixed point), against
// `direct` on upsetting with a rough top die.
//~ feature = "ipopt"
//~ scene = "upsetting_friction to 2 mm, friction factor m = 0.1 and Coulomb mu = 0.1, ipopt against direct"
//~ source = "paper eq. 10-12 (arctan friction; ipopt holds it in the objective with bounds from the multipliers)"
//~ [[check]]
//~ what = "die load against direct's, every step"
//~ compares = "another formulation"
//~ tolerance = "1e-5 (relative)"
//~ why = "measured 5.6e-10 (m) and 6.4e-9 (mu); 1e-5 leaves the Coulomb fixed point's tolerance (1e-6) room"
//~ [[check]]
//~ what = "the friction bounds' change over the last pass (friction_change)"
//~ compares = "expected behaviour"
//~ tolerance = "1e-6"
//~ why = "the fixed point's stopping tolerance (friction_tolerance)"
//~ [[check]]
//~ what = "Kuhn-Tucker residuals (primal, complementarity, stationarity)"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8"
//~ why = "as every ipopt run"
TEST(Ipopt, DieFrictionMatchesDirect) {
  const std::string set = " --set stepping.end_stroke=2.0";
  for (const std::string variant : {"", "mu0.1"}) {
    const std::string v = variant.empty() ? "" : " --variant " + variant;
    const std::string ip = run_case("upsetting_friction", "--formulation ipopt" + v + set, 0, "_ipopt" + variant);
    const std::string di = run_case("upsetting_friction", "--formulation direct" + v + set, 0, "_direct" + variant);
    const History hi = read_history(ip + "/history.csv"), hd = read_history(di + "/history.csv");
    ASSERT_EQ(hi.rows(), hd.rows());
    double load = 0, change = 0, kkt = 0, passes = 0;
    for (std::size_t i = 0; i < hi.rows(); ++i) {
      ASSERT_NEAR(hi.at("stroke")[i], hd.at("stroke")[i], 1e-12);
      load = std::max(load, std::abs(hi.at("top_die.Fy")[i] / hd.at("top_die.Fy")[i] - 1));
      change = std::max(change, hi.at("friction_change")[i]);
      kkt = std::max({kkt, hi.at("kkt_primal")[i], hi.at("kkt_complementarity")[i], hi.at("kkt_stationarity")[i]});
      passes = std::max(passes, hi.at("contact_passes")[i]);
    }
    EXPECT_LT(load, 1e-5) << variant;
    EXPECT_LE(change, 1e-6) << variant;
    EXPECT_LT(kkt, 1e-8) << variant;
    std::printf("[measured] upsetting to 2 mm, %s: ipopt vs direct load %.2e, friction fixed point to %.1e in at most "
                "%g solves per step, Kuhn-Tucker residuals %.2e\n",
                variant.empty() ? "m = 0.1" : "mu = 0.1", load, change, passes, kkt);
  }
}

// A solve's first friction bounds extrapolated from the last settled
// solves (predict_bounds) and the passes that only give the next bounds
// solved to loose_tol: upsetting mu = 0.1 to 3 mm in fewer passes and
// Ipopt iterations than from the last step's forces and to tol, at the
// same loads (the fixed point is converged to friction_tolerance either way).
//~ feature = "ipopt"
//~ scene = "upsetting_friction mu0.1 to 3 mm, ipopt with and without predicted bounds and loose passes"
//~ source = "paper eq. 10-12 (the Coulomb bound's fixed point)"
//~ [[check]]
//~ what = "die load against the runs from the last step's forces and with loose_tol = tol, every step"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-7 (relative)"
//~ why = "the fixed point is converged to friction_tolerance either way: only its tolerance separates them"
//~ [[check]]
//~ what = "friction passes: predicted bounds below 0.8 of the plain start's; Ipopt iterations fewer than with loose_tol = tol"
//~ compares = "the same scene run otherwise"
//~ tolerance = "< 0.8 x passes"
//~ why = "the option exists to save passes; a fifth is the least gain that justifies it"
//~ [[check]]
//~ what = "friction_change of both runs"
//~ compares = "expected behaviour"
//~ tolerance = "1e-6"
//~ why = "the fixed point's stopping tolerance"
TEST(Ipopt, PredictedBoundsAndLoosePassesKeepTheLoadsInFewerPasses) {
  const std::string set = "--formulation ipopt --variant mu0.1 --set stepping.end_stroke=3.0";
  const History fast = read_history(run_case("upsetting_friction", set, 0, "_fast") + "/history.csv");
  const History last = read_history(
      run_case("upsetting_friction", set + " --set formulations.ipopt.predict_bounds=false", 0, "_last") +
      "/history.csv");
  const History tight = read_history(
      run_case("upsetting_friction", set + " --set formulations.ipopt.loose_tol=1e-10", 0, "_tight") +
      "/history.csv");
  ASSERT_EQ(fast.rows(), last.rows());
  ASSERT_EQ(fast.rows(), tight.rows());
  double to_last = 0, to_tight = 0, change = 0;
  const auto sum = [](const History& h, const std::string& c) {
    double t = 0;
    for (double v : h.at(c)) t += v;
    return t;
  };
  for (std::size_t i = 1; i < fast.rows(); ++i) {
    ASSERT_NEAR(fast.at("stroke")[i], last.at("stroke")[i], 1e-9);
    ASSERT_NEAR(fast.at("stroke")[i], tight.at("stroke")[i], 1e-9);
    to_last = std::max(to_last, std::abs(fast.at("top_die.Fy")[i] / last.at("top_die.Fy")[i] - 1));
    to_tight = std::max(to_tight, std::abs(fast.at("top_die.Fy")[i] / tight.at("top_die.Fy")[i] - 1));
    change = std::max({change, fast.at("friction_change")[i], last.at("friction_change")[i]});
  }
  EXPECT_LT(to_last, 1e-7);
  EXPECT_LT(to_tight, 1e-7);
  EXPECT_LE(change, 1e-6);
  EXPECT_LT(sum(fast, "contact_passes"), 0.8 * sum(last, "contact_passes"));
  EXPECT_LT(sum(fast, "newton_iterations"), sum(tight, "newton_iterations"));
  std::printf("[measured] upsetting mu = 0.1 to 3 mm: passes %g predicted, %g from the last step's forces; Ipopt "
              "iterations %g, %g, %g with loose_tol = tol; loads within %.1e and %.1e\n",
              sum(fast, "contact_passes"), sum(last, "contact_passes"), sum(fast, "newton_iterations"),
              sum(last, "newton_iterations"), sum(tight, "newton_iterations"), to_last, to_tight);
}

namespace {

// The largest relative difference of `load` between `penalty` at each beta
// factor and `ipopt`, step by step (the same strokes: without landing
// control, whose landing strokes follow each run's own velocities).
std::vector<double> penalty_to_ipopt(const std::string& scene, const std::string& set, const std::string& load,
                                     const std::vector<std::string>& factors) {
  const std::string fixed = set + " --set contact.landing_control=false";
  const History hi = read_history(run_case(scene, "--formulation ipopt" + fixed, 0, "_ipopt") + "/history.csv");
  std::vector<double> diff;
  for (const std::string& f : factors) {
    const std::string pe =
        run_case(scene, "--formulation penalty --set formulations.penalty.beta_factor=" + f + fixed, 0, "_penalty" + f);
    const History hp = read_history(pe + "/history.csv");
    EXPECT_EQ(hp.rows(), hi.rows());
    double d = 0;
    for (std::size_t i = 0; i < std::min(hp.rows(), hi.rows()); ++i) {
      EXPECT_DOUBLE_EQ(hp.at("stroke")[i], hi.at("stroke")[i]);
      d = std::max(d, std::abs(hp.at(load)[i] / hi.at(load)[i] - 1));
    }
    diff.push_back(d);
  }
  return diff;
}

// Beta factors two decades apart: the difference falls at first order in
// 1 / beta (the penalty's compliance) to below 1e-7, far from Ipopt's own
// tolerance. Prints the measured differences and orders after `what`.
void expect_first_order(const std::vector<double>& diff, const std::vector<std::string>& factors,
                        const std::string& what) {
  const double order1 = std::log10(diff[0] / diff[1]) / 2, order2 = std::log10(diff[1] / diff[2]) / 2;
  EXPECT_NEAR(order1, 1.0, 0.1);
  EXPECT_NEAR(order2, 1.0, 0.1);
  EXPECT_LT(diff[2], 1e-7);
  std::printf("[measured] %s, penalty vs ipopt load: %.2e, %.2e, %.2e at beta %s, %s, %s x default; observed order "
              "%.3f, %.3f\n",
              what.c_str(), diff[0], diff[1], diff[2], factors[0].c_str(), factors[1].c_str(), factors[2].c_str(),
              order1, order2);
}

}  // namespace

// The penalty solution converges to Ipopt's as beta grows: ring compression
// with m = 0.1 to 0.5 mm at beta 1e-3, 1e-1 and 1e1 times the default.
//~ feature = "ipopt"
//~ scene = "ring_compression m0.1 to 0.5 mm, penalty at 1e-3, 1e-1, 1e1 x the default beta against ipopt"
//~ source = "paper eq. 7-8: the penalty's compliance is O(1 / beta)"
//~ [[check]]
//~ what = "observed order of the load difference per decade of beta"
//~ compares = "another formulation"
//~ tolerance = "1.0 +- 0.1"
//~ why = "measured 1.00 per decade down to 3e-9 on the whole ring; 0.1 allows Ipopt's tolerance at the finest"
//~ [[check]]
//~ what = "load difference at the largest beta"
//~ compares = "another formulation"
//~ tolerance = "1e-7 (relative)"
//~ why = "far from Ipopt's own tolerance: the penalty solution reaches the exact one"
TEST(Ipopt, PenaltyConvergesToItAsBetaGrows) {
  const std::vector<std::string> factors{"1e-3", "1e-1", "1e1"};
  const auto diff =
      penalty_to_ipopt("ring_compression", " --variant m0.1 --set stepping.end_stroke=0.5", "top_die.Fy", factors);
  expect_first_order(diff, factors, "ring m = 0.1 to 0.5 mm");
}

// The same on Test II's conical punch with Coulomb friction (mu = 0.1) to
// 0.5 mm, where nodes land on the cone one by one: the sticking cap k w
// that bounds mu N is set over the contact area of the solution in both
// formulations, so each landing step converges too.
//~ feature = "ipopt"
//~ scene = "paper_test2_die to 0.5 mm, Coulomb mu = 0.1, penalty at 1e-2, 1, 1e2 x the default beta against ipopt"
//~ source = "paper eq. 7-8 and 10-12; paper Test II (Fig. 8-11)"
//~ [[check]]
//~ what = "observed order of the load difference per decade of beta"
//~ compares = "another formulation"
//~ tolerance = "1.0 +- 0.1"
//~ why = "measured 1.000 and 0.986; a stale sticking cap in penalty gave order -0.01 (9.5e-3 at every beta), which this catches"
//~ [[check]]
//~ what = "load difference at the largest beta"
//~ compares = "another formulation"
//~ tolerance = "1e-7 (relative)"
//~ why = "the sticking cap k w is set over the contact area of the solution in both, so each landing step converges too"
TEST(Ipopt, PenaltyConvergesToItUnderCoulombFriction) {
  const std::vector<std::string> factors{"1e-2", "1e0", "1e2"};
  const auto diff = penalty_to_ipopt("paper_test2_die", " --set stepping.end_stroke=0.5", "punch.Fy", factors);
  expect_first_order(diff, factors, "Test II mu = 0.1 to 0.5 mm");
}

// Test II's rigid die to 0.3 mm: the first solve (a point contact carrying
// 180 N, far smaller than the forces at Ipopt's starting point) meets the
// checked complementarity too, and every residual holds to 1e-8.
//~ feature = "ipopt"
//~ scene = "paper_test2_die under ipopt to 0.3 mm"
//~ source = "paper eq. 6; paper Test II (Fig. 8-11)"
//~ [[check]]
//~ what = "complementarity at the first solve (a point contact carrying 180 N), and every residual at every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8 (complementarity, dual, stationarity), 1e-9 (primal)"
//~ why = "the first solve's forces are far below those at Ipopt's starting point, which set its scale; the solve is repeated from its own solution when it misses 1e-8 (measured 3.6e-11 at the first solve, 3.6e-9 at worst)"
TEST(Ipopt, TestTwoDieFirstContactMeetsTheKuhnTuckerConditions) {
  const std::string ip = run_case("paper_test2_die", "--formulation ipopt --set stepping.end_stroke=0.3");
  const History h = read_history(ip + "/history.csv");
  ASSERT_GE(h.rows(), 7u);  // 6 steps, and the landing steps
  ASSERT_NEAR(h.at("stroke").back(), 0.3, 1e-9);
  double kkt = 0, pen = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    pen = std::max(pen, h.at("kkt_primal")[i]);
    kkt = std::max({kkt, h.at("kkt_dual")[i], h.at("kkt_complementarity")[i], h.at("kkt_stationarity")[i]});
  }
  EXPECT_GT(std::abs(h.at("punch.Fy")[0]), 100.0);  // the first solve presses
  EXPECT_LT(h.at("kkt_complementarity")[0], 1e-8);
  EXPECT_LT(kkt, 1e-8);
  EXPECT_LT(pen, 1e-9);
  std::printf("[measured] Test II die to 0.3 mm: first-solve complementarity %.2e, worst Kuhn-Tucker residual %.2e, "
              "penetration / element size %.2e\n",
              h.at("kkt_complementarity")[0], kkt, pen);
}

// Test II's die with Coulomb friction to 0.5 mm (without landing control:
// the same strokes): warm starts (the friction passes from the last
// multipliers, a step's first solve from the last forces) give the plain
// starts' loads in fewer Ipopt iterations, and are no farther than they
// from a solution to a hundred times tighter tolerances.
//~ feature = "ipopt"
//~ scene = "paper_test2_die to 0.5 mm, Coulomb, warm against plain starts and a run to 100 x tighter tolerances"
//~ source = "Waechter and Biegler 2006 (warm starts of the interior point)"
//~ [[check]]
//~ what = "punch load, warm against plain starts"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-7 (relative)"
//~ why = "the same solution to Ipopt's and the fixed point's tolerances"
//~ [[check]]
//~ what = "warm starts no farther than plain ones from the tight run; fewer than 0.6 of the iterations"
//~ compares = "the same scene run otherwise"
//~ tolerance = "<= plain's error; < 0.6 x iterations"
//~ why = "a warm start must not trade accuracy for speed; 0.6 is the gain that justifies the option"
TEST(Ipopt, WarmStartsGiveThePlainStartsLoadsInFewerIterations) {
  const std::string set = " --formulation ipopt --set stepping.end_stroke=0.5 --set contact.landing_control=false";
  const History warm = read_history(run_case("paper_test2_die", set, 0, "_warm") + "/history.csv");
  const History plain = read_history(
      run_case("paper_test2_die", set + " --set formulations.ipopt.warm_start=false", 0, "_plain") + "/history.csv");
  const History tight = read_history(run_case("paper_test2_die",
                                              set + " --set formulations.ipopt.warm_start=false --set "
                                                    "formulations.ipopt.tol=1e-12 --set "
                                                    "formulations.ipopt.friction_tolerance=1e-8",
                                              0, "_tight") +
                                     "/history.csv");
  ASSERT_EQ(warm.rows(), 11u);
  ASSERT_EQ(plain.rows(), warm.rows());
  ASSERT_EQ(tight.rows(), warm.rows());
  double between = 0, warm_err = 0, plain_err = 0, its_warm = 0, its_plain = 0;
  for (std::size_t i = 0; i < warm.rows(); ++i) {
    const double w = warm.at("punch.Fy")[i], p = plain.at("punch.Fy")[i], t = tight.at("punch.Fy")[i];
    between = std::max(between, std::abs(w / p - 1));
    warm_err = std::max(warm_err, std::abs(w / t - 1));
    plain_err = std::max(plain_err, std::abs(p / t - 1));
    its_warm += warm.at("newton_iterations")[i], its_plain += plain.at("newton_iterations")[i];
  }
  EXPECT_LT(between, 1e-7);
  EXPECT_LE(warm_err, plain_err);
  EXPECT_LT(its_warm, 0.6 * its_plain);
  EXPECT_EQ(warm.at("warm_fallbacks").front(), 0.0);
  std::printf("[measured] Test II die to 0.5 mm: warm against plain starts %.2e; against tight tolerances: warm %.2e, "
              "plain %.2e; Ipopt iterations %g warm, %g plain; warm starts solved again %g\n",
              between, warm_err, plain_err, its_warm, its_plain, warm.at("warm_fallbacks").back());
}

// Test II's virtual rigid body to 0.15 mm: the residual's own evaluation
// noise (kkt_round_off: R at u moved by one ulp) is above 1e-8 at the first
// solve, and stationarity is within it at every step; the contact
// conditions hold to 1e-8.
//~ feature = "ipopt"
//~ scene = "paper_test2_virtual_rigid under ipopt to 0.15 mm"
//~ source = "paper Test II (Fig. 8-11); the residual's round-off floor kkt_round_off (R at u moved by one ulp)"
//~ [[check]]
//~ what = "stationarity / max(1e-8, kkt_round_off), every step; the floor above 1e-7 at the first solve"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "<= 1.0"
//~ why = "the virtual rigid body's stiffness (1e5 of the billet's) puts the residual's own evaluation noise above 1e-8 (3e-6 at the first step): no solver can go below it, so each step is held to the larger of the two (measured: at most 0.40 of it)"
//~ [[check]]
//~ what = "contact residuals (primal, dual, complementarity)"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8"
//~ why = "the contact conditions are not affected by the floor"
TEST(Ipopt, VirtualRigidBodyStationarityIsAtItsRoundOffFloor) {
  const std::string ip = run_case("paper_test2_virtual_rigid", "--formulation ipopt --set stepping.end_stroke=0.15");
  const History h = read_history(ip + "/history.csv");
  ASSERT_GE(h.rows(), 4u);  // 3 steps, and the landing steps
  ASSERT_NEAR(h.at("stroke").back(), 0.15, 1e-9);
  EXPECT_GT(h.at("kkt_round_off")[0], 1e-7);
  double ratio = 0, contact = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    ratio = std::max(ratio, h.at("kkt_stationarity")[i] / std::max(1e-8, h.at("kkt_round_off")[i]));
    contact = std::max({contact, h.at("kkt_primal")[i], h.at("kkt_dual")[i], h.at("kkt_complementarity")[i]});
  }
  EXPECT_LE(ratio, 1.0);
  EXPECT_LT(contact, 1e-8);
  std::printf("[measured] virtual rigid body to 0.15 mm: first-solve stationarity %.2e, its round-off floor %.2e; "
              "largest stationarity / max(1e-8, floor) %.2f; contact residuals %.2e\n",
              h.at("kkt_stationarity")[0], h.at("kkt_round_off")[0], ratio, contact);
}

// The same body on the coarse mesh (mesh factor 0.5) with mortar rows: at
// the first touch nothing is loaded (the rows' weighted gaps close over a
// step or two), every force is round-off of the force floor, and Ipopt
// stalls at its acceptable point with complementarity 7e-7 and
// stationarity 3e-5, both within ten times the residual's own round-off
// (4.5e-5); those solves are taken, and the run reaches 0.15 mm (it
// stopped at step 1). Where the residual's round-off is below the checks'
// tolerances the checks hold as before.
//~ feature = "ipopt"
//~ scene = "paper_test2_virtual_rigid with mortar rows at mesh factor 0.5, to 0.15 mm"
//~ source = "the residual's round-off floor kkt_round_off; Puso and Laursen 2004 (the mortar rows)"
//~ [[check]]
//~ what = "dual and complementarity residuals / max(1e-8, 10 x kkt_round_off), every step; the run reaches 0.15 mm"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "<= 1.0 with 10 x the floor"
//~ why = "at the first touch nothing is loaded (the rows' weighted gaps close over a step or two) and every force is round-off of the force floor: Ipopt may stall at its acceptable point, and such a solve is taken when its residuals are within ten times the residual's own round-off"
//~ [[check]]
//~ what = "kkt_primal, every step"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-9"
//~ why = "the gap holds to solver precision even there"
TEST(Ipopt, AStepWithNothingLoadedIsSolvedToTheResidualsRoundOff) {
  const std::string ip = run_case("paper_test2_virtual_rigid",
                                  "--formulation ipopt --set contact.discretization=mortar --set run.mesh_factor=0.5 "
                                  "--set stepping.end_stroke=0.15",
                                  0, "_mortar_coarse");
  const History h = read_history(ip + "/history.csv");
  ASSERT_GE(h.rows(), 4u);
  ASSERT_NEAR(h.at("stroke").back(), 0.15, 1e-9);
  double worst = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    const double limit = std::max(1e-8, 10 * h.at("kkt_round_off")[i]);
    worst = std::max({worst, h.at("kkt_dual")[i] / limit, h.at("kkt_complementarity")[i] / limit});
    EXPECT_LE(h.at("kkt_primal")[i], 1e-9);
  }
  EXPECT_LE(worst, 1.0);
  std::printf("[measured] mortar virtual rigid body, mesh factor 0.5, to 0.15 mm: %zu steps, largest contact residual "
              "/ max(1e-8, 10 x its round-off) %.2f\n",
              h.rows() - 1, worst);
}

// MUMPS's analysis kept across a program's passes
// (formulations/ipopt/mumps_analysis_reuse.hpp): Test II's die to 0.5 mm
// gives the same history to the bit with and without reuse, in a fraction
// of the analyses; with MUMPS's value-dependent analysis (Ipopt's default
// mumps_permuting_scaling = 7) nothing is reused and the loads stay within
// 1e-9 of the largest.
//~ feature = "ipopt"
//~ scene = "paper_test2_die to 0.5 mm, MUMPS analyses reused or not, and MUMPS's value-dependent analysis"
//~ source = "formulations/ipopt/mumps_analysis_reuse.hpp"
//~ [[check]]
//~ what = "every history column, with and without reuse"
//~ compares = "the same scene run otherwise"
//~ tolerance = "equal bits"
//~ why = "reusing the symbolic analysis of the same pattern changes no arithmetic"
//~ [[check]]
//~ what = "analyses reused more than twice those done; with mumps_permuting_scaling = 7 none reused and the loads within 1e-9 of the largest"
//~ compares = "the same scene run otherwise"
//~ tolerance = "> 2 x; 1e-9 of the largest load"
//~ why = "a value-dependent analysis permutes differently: only round-off may change"
TEST(Ipopt, ReusedMumpsAnalysesGiveTheSameBits) {
  const std::string set = "--formulation ipopt --set stepping.end_stroke=0.5";
  const auto run = [&](const std::string& suffix, const std::string& more) {
    return read_history(run_case("paper_test2_die", set + more, 0, suffix) + "/history.csv");
  };
  const History on = run("_reuse", ""),
                off = run("_analyse", " --set formulations.ipopt.reuse_mumps_analysis=false");
  ASSERT_EQ(on.rows(), off.rows());
  ASSERT_GT(on.rows(), 2u);
  ASSERT_EQ(on.columns, off.columns);
  for (const std::string& c : on.columns) {
    if (c == "mumps_analyses" || c == "mumps_analyses_reused") continue;
    for (std::size_t i = 0; i < on.rows(); ++i) ASSERT_EQ(on.at(c)[i], off.at(c)[i]) << c << ", row " << i;
  }
  const double analysed = on.at("mumps_analyses").back(), reused = on.at("mumps_analyses_reused").back();
  EXPECT_EQ(off.at("mumps_analyses_reused").back(), 0.0);
  EXPECT_EQ(analysed + reused, off.at("mumps_analyses").back());
  EXPECT_GT(reused, 2 * analysed);
  const History automatic = run("_auto", " --set formulations.ipopt.mumps_permuting_scaling=7");
  ASSERT_EQ(automatic.rows(), on.rows());
  EXPECT_EQ(automatic.at("mumps_analyses_reused").back(), 0.0);
  double load = 0, largest = 0;
  for (std::size_t i = 0; i < on.rows(); ++i) {
    load = std::max(load, std::abs(automatic.at("punch.Fy")[i] - on.at("punch.Fy")[i]));
    largest = std::max(largest, std::abs(on.at("punch.Fy")[i]));
  }
  EXPECT_LT(load, 1e-9 * largest);
  std::printf("[measured] Test II die to 0.5 mm under ipopt: %g MUMPS analyses and %g reused against %g analysed "
              "without reuse; MUMPS's automatic analysis against the pattern's: loads %.1e of the largest apart\n",
              analysed, reused, off.at("mumps_analyses").back(), load / largest);
}

namespace {

// One case under ssn and under ipopt with exact friction, to `stroke`:
// the largest relative difference of the die load over the steps, of the
// ring's inner-diameter change (if `diameter`), the steps whose sticking
// and slipping rows differ, and whether the last step's stick_slip fields
// are the same node for node.
struct ExactPair {
  double load = 0, diameter = 0;
  int stick_steps_differing = 0;
  bool same_last_field = false;
  double stick_last = 0, slip_last = 0;
  double ipopt_kkt_friction = 0, ipopt_kkt_stick_slip = 0, ipopt_kkt_primal = 0, ipopt_kkt_complementarity = 0;
  double ssn_iterations = 0, ipopt_iterations = 0, ipopt_passes = 0, polished = 0;
  std::size_t steps = 0;
};

ExactPair exact_pair(const std::string& scene, const std::string& variant, const std::string& stroke, bool diameter) {
  const std::string set = " --variant " + variant + " --set stepping.end_stroke=" + stroke +
                          " --set dies.top_die.friction.regularization=exact";
  const std::string ss = run_case(scene, "--enforcement ssn" + set, 0, "_ssn_" + variant);
  const std::string ip = run_case(scene, "--enforcement ipopt" + set, 0, "_ipopt_" + variant);
  const History hs = read_history(ss + "/history.csv"), hi = read_history(ip + "/history.csv");
  ExactPair out;
  EXPECT_EQ(hi.rows(), hs.rows()) << scene << " " << variant;
  out.steps = std::min(hi.rows(), hs.rows());
  for (std::size_t i = 0; i < out.steps; ++i) {
    EXPECT_NEAR(hi.at("stroke")[i], hs.at("stroke")[i], 1e-12) << "step " << i;
    out.load = std::max(out.load, std::abs(hi.at("top_die.Fy")[i] / hs.at("top_die.Fy")[i] - 1));
    if (diameter && hs.at("inner_diameter_mid")[i] != 0)
      out.diameter = std::max(out.diameter, std::abs(hi.at("inner_diameter_mid")[i] / hs.at("inner_diameter_mid")[i] - 1));
    out.stick_steps_differing += hi.at("stick_rows")[i] != hs.at("stick_rows")[i] || hi.at("slip_rows")[i] != hs.at("slip_rows")[i];
    out.ipopt_kkt_friction = std::max(out.ipopt_kkt_friction, hi.at("kkt_friction")[i]);
    out.ipopt_kkt_stick_slip = std::max(out.ipopt_kkt_stick_slip, hi.at("kkt_stick_slip")[i]);
    out.ipopt_kkt_primal = std::max(out.ipopt_kkt_primal, hi.at("kkt_primal")[i]);
    out.ipopt_kkt_complementarity = std::max(out.ipopt_kkt_complementarity, hi.at("kkt_complementarity")[i]);
    out.ssn_iterations += hs.at("newton_iterations")[i];
    out.ipopt_iterations += hi.at("newton_iterations")[i];
    out.ipopt_passes += hi.at("contact_passes")[i];
    out.polished += hi.at("polished")[i];
  }
  out.stick_last = hs.at("stick_rows").back(), out.slip_last = hs.at("slip_rows").back();
  const std::vector<int> ks = read_h5_steps(ss + "/result.h5"), ki = read_h5_steps(ip + "/result.h5");
  if (!ks.empty() && !ki.empty() && ks.back() == ki.back()) {
    char g[64];
    std::snprintf(g, sizeof g, "/steps/%06d/node/stick_slip", ks.back());
    out.same_last_field = read_h5_dataset(ss + "/result.h5", g) == read_h5_dataset(ip + "/result.h5", g);
  }
  return out;
}

}  // namespace

// The two exact enforcements check each other: ipopt's slack rows
// (formulations/ipopt/ipopt_step_solver.hpp) against ssn's complementarity
// functions (formulations/ssn/ncp.hpp), to 1 mm of stroke (20 steps): the
// ring at m = 0.1 (no row sticks: both sides of the neutral radius slip)
// and m = 1 (a sticking zone), upsetting at mu = 0.1 (every row slips).
// Die loads and the ring's inner-diameter change within 1e-6, the same
// rows sticking and slipping at every step, and ipopt's friction law met
// to 1e-8 of each row's bound.
//~ feature = "ssn"
//~ scene = "ring_compression m0.1 and m1, upsetting_friction mu0.1, exact friction, to 1 mm (20 steps), ipopt against ssn"
//~ source = "Hueber, Stadler and Wohlmuth 2008 (ssn's complementarity functions); Waechter and Biegler 2006 (ipopt's slack rows): two implementations of the same conditions"
//~ [[check]]
//~ what = "die load and the ring's inner-diameter change, every step"
//~ compares = "another formulation"
//~ tolerance = "1e-6 (relative)"
//~ why = "both solve the same exact conditions to 1e-8; 1e-6 is their tolerances carried through the steps with margin"
//~ [[check]]
//~ what = "the same rows sticking and slipping at every step; the last step's stick_slip field node for node"
//~ compares = "another formulation"
//~ tolerance = "equal"
//~ why = "the active sets of an exact law are determined by the solution"
//~ [[check]]
//~ what = "ipopt's friction law (kkt_friction, kkt_stick_slip) and contact residuals"
//~ compares = "Kuhn-Tucker conditions"
//~ tolerance = "1e-8 (friction, complementarity), 1e-9 (primal)"
//~ why = "the exact enforcements' targets"
TEST(Ipopt, ExactFrictionAgreesWithSsn) {
  struct Case {
    std::string scene, variant;
    bool diameter;
  };
  for (const Case& c : {Case{"ring_compression", "m0.1", true}, Case{"ring_compression", "m1", true},
                        Case{"upsetting_friction", "mu0.1", false}}) {
    const ExactPair p = exact_pair(c.scene, c.variant, "1.0", c.diameter);
    const std::string what = c.scene + " " + c.variant;
    ASSERT_EQ(p.steps, 21u) << what;
    EXPECT_LT(p.load, 1e-6) << what;
    if (c.diameter) EXPECT_LT(p.diameter, 1e-6) << what;
    EXPECT_EQ(p.stick_steps_differing, 0) << what;
    EXPECT_TRUE(p.same_last_field) << what;
    EXPECT_LE(p.ipopt_kkt_friction, 1e-8) << what;
    EXPECT_LE(p.ipopt_kkt_stick_slip, 1e-8) << what;
    EXPECT_LE(p.ipopt_kkt_primal, 1e-9) << what;
    EXPECT_LE(p.ipopt_kkt_complementarity, 1e-8) << what;
    std::printf("[measured] %s to 1 mm, ipopt against ssn (exact friction): load %.2e, inner diameter change %.2e; "
                "last step %g rows sticking, %g slipping, stick-slip differing in %d of %zu steps; ipopt's kkt_friction "
                "%.1e, kkt_stick_slip %.1e; Newton iterations %g (ssn), Ipopt iterations %g in %g passes, %g of %zu "
                "steps polished\n",
                what.c_str(), p.load, p.diameter, p.stick_last, p.slip_last, p.stick_steps_differing, p.steps,
                p.ipopt_kkt_friction, p.ipopt_kkt_stick_slip, p.ssn_iterations, p.ipopt_iterations, p.ipopt_passes,
                p.polished, p.steps);
  }
}
