// Requirement (kernel): step control by a local error estimate
// (stepping.tolerance, model/step_control.hpp). On the frictionless
// upsetting with its exact solution the achieved error of the press load
// follows the stated tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "analytic.hpp"
#include "results.hpp"
#include "run_case.hpp"
#include "sweep_metrics.hpp"

using namespace rpfem;
using accept::aisi1035;
using accept::run_case;

namespace {

struct Achieved {
  double error = 0;  // max_s |F_h(s) - F(s)| / max_s |F(s)| (docs/theory.md, "Step control")
  int steps = 0;
};

// The frictionless upsetting (exact: homogeneous, verification/analytic.hpp)
// at tolerance tol under the given integration; a 4 x 4 mesh (the flow is
// homogeneous: the mesh adds no error), fields at the last step only.
Achieved upsetting_at(double tol, const std::string& integration, const std::string& suffix) {
  char extra[400];
  std::snprintf(extra, sizeof extra,
                "--set stepping.tolerance=%g --set stepping.integration=%s --set bodies.billet.mesh.nx=4 "
                "--set bodies.billet.mesh.ny=4 --set stepping.output_every=100000",
                tol, integration.c_str());
  const std::string dir = run_case("upsetting_frictionless_axisym", extra, 0, suffix);
  const History h = read_history(dir + "/history.csv");
  const auto& s = h.at("stroke");
  const auto& F = h.at("top_platen.Fy");
  double worst = 0, largest = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    const double exact = upsetting_load_axisymmetric(aisi1035(false), 20, 20, 20 - 2 * s[i]);
    worst = std::max(worst, std::abs(-F[i] - exact));
    largest = std::max(largest, exact);
  }
  EXPECT_NEAR(s.back(), 5.0, 1e-9) << "the run must reach 50 % reduction";
  EXPECT_GT(h.at("step_error_bound").back(), 0.0) << "the estimate's bound in history.csv";
  return {worst / largest, int(h.rows()) - 1};
}

}  // namespace

//~ feature = "upsetting"
//~ scene = "upsetting_frictionless_axisym, explicit Euler, stepping.tolerance 1e-2, 1e-3 and 1e-4, a 4 x 4 mesh"
//~ source = "Kobayashi, Oh and Altan 1989, sec. 5.2 (exact load); Hairer, Norsett and Wanner, Solving ODEs I, sec. II.4 (step-size control by an embedded pair)"
//~ [[check]]
//~ what = "achieved error of the press load, max over the stroke of |F_h - F| over the largest exact load, against the stated tolerance"
//~ compares = "exact solution"
//~ tolerance = "between tol / 3 and 3 tol at each tolerance"
//~ why = "the control's promise: a run to a stated accuracy; a wrong estimate (order, scale, norm) or bound misses by more than a factor of 3"
//~ [[check]]
//~ what = "achieved error falls with the tolerance"
//~ compares = "expected behaviour"
//~ tolerance = "smaller at each smaller tolerance"
//~ why = "a controller that does not follow its tolerance does not control"
TEST(StepControl, EulerUpsettingMeetsTheTolerance) {
  double last = INFINITY;
  for (double tol : {1e-2, 1e-3, 1e-4}) {
    const Achieved a = upsetting_at(tol, "euler", std::string("_").append(std::to_string(tol)));
    std::printf("[measured] tolerance %.0e: achieved %.3e (ratio %.2f) in %d steps\n", tol, a.error, a.error / tol,
                a.steps);
    EXPECT_GT(a.error, tol / 3) << tol;
    EXPECT_LT(a.error, 3 * tol) << tol;
    EXPECT_LT(a.error, last) << tol;
    last = a.error;
  }
}

//~ feature = "ring"
//~ scene = "ring_compression (direct, m = 0.1), explicit Euler, stepping.tolerance 1e-2 and 1e-3; reference: the same case with fixed midpoint steps of 0.005 mm (a tenth of the case's)"
//~ source = "Hairer, Norsett and Wanner, Solving ODEs I, sec. II.4 (step-size control); the reference's own error against 0.0025 mm steps, 5e-5, is below the tolerances' achieved errors"
//~ [[check]]
//~ what = "achieved error of the press load against the reference, max over the strokes away from the landings of |F_h - F_ref| over the largest reference load"
//~ compares = "the same scene run otherwise"
//~ tolerance = "between tol / 3 and 3 tol at each tolerance, falling with it"
//~ why = "the control's promise on a scene with contact and friction; measured 0.69 and 0.67 times the tolerance (0.70 and 0.68 against 0.0025 mm steps)"
TEST(StepControl, EulerRingMeetsTheTolerance) {
  const std::string ref_dir = run_case("ring_compression",
                                       "--set stepping.stroke_increment=0.005 --set stepping.output_every=100000", 0,
                                       "_ref");
  const History ref = read_history(ref_dir + "/history.csv");
  double last = INFINITY;
  for (double tol : {1e-2, 1e-3}) {
    char extra[300];
    std::snprintf(extra, sizeof extra,
                  "--set stepping.tolerance=%g --set stepping.integration=euler --set stepping.output_every=100000",
                  tol);
    const std::string dir = run_case("ring_compression", extra, 0, std::string("_").append(std::to_string(tol)));
    const History h = read_history(dir + "/history.csv");
    EXPECT_NEAR(h.at("stroke").back(), 5.0, 1e-9);
    const double a = max_relative_load_error(h, ref, "top_die.Fy");
    std::printf("[measured] ring, tolerance %.0e: achieved %.3e (ratio %.2f) in %zu steps\n", tol, a, a / tol,
                h.rows() - 1);
    EXPECT_GT(a, tol / 3) << tol;
    EXPECT_LT(a, 3 * tol) << tol;
    EXPECT_LT(a, last) << tol;
    last = a;
  }
}

// Test II's punch lands its nodes one by one as the cone's contact spreads.
// Under Euler with step control a step's end solve is the next step's
// start velocity, and the next step's length is chosen after it: were it to
// anticipate the landings within its own step (a node still open pressed
// already), the next, shorter step found the node open and let it go, the
// pair's difference was first order in the step there, and the step was
// kept at the least increment above its bound (ssn: each punch node touched
// 3 times, 10 steps above the bound; penalty: 2 to 4, 12 steps).
//~ feature = "test2"
//~ scene = "paper_test2_die on the half mesh to 0.5 mm under ssn and penalty, explicit Euler, stepping.tolerance 1e-3"
//~ source = "Hairer, Norsett and Wanner, Solving ODEs I, sec. II.4 (the embedded pair's estimate is second order in the step only where the solution is smooth over it)"
//~ [[check]]
//~ what = "each punch node touches once and is never released in a kept step (events.csv)"
//~ compares = "expected behaviour"
//~ tolerance = "no kept release on the punch"
//~ why = "the punch's contact zone only grows; a node let go at its landing and pressed again is the anticipation of a step of another length"
//~ [[check]]
//~ what = "steps kept with the local error estimate above its bound (history.csv step_error, step_error_bound)"
//~ compares = "expected behaviour"
//~ tolerance = "none"
//~ why = "a landing inside a step makes the estimate first order in the step, which no shorter step brings under the bound; landing control ends the step at it instead"
TEST(StepControl, EulerLandsEachPunchNodeOnce) {
  for (const char* f : {"ssn", "penalty"}) {
    const std::string dir = run_case("paper_test2_die",
                                     std::string("--formulation ") + f +
                                         " --set stepping.integration=euler --set stepping.tolerance=1e-3 "
                                         "--set stepping.end_stroke=0.5 --set run.mesh_factor=0.5 "
                                         "--set stepping.output_every=100000",
                                     0, std::string("_") + f);
    const std::string events = read_text(dir + "/events.csv");
    int touches = 0, releases = 0;
    std::size_t at = 0;
    for (std::size_t end; (end = events.find('\n', at)) != std::string::npos; at = end + 1) {
      const std::string line = events.substr(at, end - at);
      if (line.find("punch") == std::string::npos) continue;
      touches += line.find(",kept,touch node") != std::string::npos;
      releases += line.find(",kept,release node") != std::string::npos;
    }
    EXPECT_GE(touches, 3) << f << ": the punch's nodes land within 0.5 mm";
    EXPECT_EQ(releases, 0) << f << ": a punch node let go after its landing";
    const History h = read_history(dir + "/history.csv");
    const auto &e = h.at("step_error"), &b = h.at("step_error_bound");
    int above = 0;
    for (std::size_t i = 0; i < h.rows(); ++i) above += e[i] > b[i];
    EXPECT_EQ(above, 0) << f << ": steps kept above the estimate's bound";
  }
}
