// Newton's watchdog (solver/newton.hpp): with a merit anchored at every
// iterate, a line search that accepts each step by its own iterate's merit
// can follow plain Newton into a cycle or away; the watchdog goes back to
// the least |R| and judges the steps after by |R|.
#include <gtest/gtest.h>

#include <cmath>

#include "solver/newton.hpp"

namespace rpfem {
namespace {

// R(u) = atan(u) - b: plain Newton from |u - atan^-1 b| beyond about 1.39
// overshoots further every iteration (Kelley 2003, sec. 1.7). The anchored
// merit is linear, R(u_k) (u - u_k): its own slope along every Newton step
// is R . du, so Armijo's test accepts each full step and the anchored line
// search is plain Newton, as a merit frozen at each iterate may be.
struct AtanProblem {
  double b = 0;
  double anchor_u = 0, anchor_R = 0;
  NewtonSystem system() {
    NewtonSystem sys;
    sys.residual = [this](const Vec& u, Vec& R, double& s) {
      R = Vec::Constant(1, std::atan(u[0]) - b);
      s = 1;
    };
    sys.anchor = [this](const Vec& u) {
      anchor_u = u[0];
      anchor_R = std::atan(u[0]) - b;
    };
    sys.energy = [this](const Vec& u) { return anchor_R * (u[0] - anchor_u); };
    sys.solve = [](const Vec& u, bool, const Vec& R, Vec& du) {
      du = Vec::Constant(1, -R[0] * (1 + u[0] * u[0]));
      return true;
    };
    return sys;
  }
};

NewtonSettings settings(int watchdog) {
  NewtonSettings s;
  s.direct_iterations = 0;
  s.tol_velocity = 1e-12;
  s.tol_force = 1e-12;
  s.watchdog = watchdog;
  return s;
}

TEST(NewtonWatchdog, RecoversWhereTheAnchoredMeritFollowsNewtonAway) {
  AtanProblem p;
  p.b = 0.2;  // root at tan(0.2) = 0.2027
  Vec u = Vec::Constant(1, 3.0);
  const NewtonResult off = newton_solve(p.system(), settings(0), u);
  EXPECT_FALSE(off.converged);
  EXPECT_FALSE(off.watchdog);

  u = Vec::Constant(1, 3.0);
  const NewtonResult on = newton_solve(p.system(), settings(6), u);
  EXPECT_TRUE(on.converged) << on.reason;
  EXPECT_TRUE(on.watchdog);
  EXPECT_NEAR(u[0], std::tan(0.2), 1e-10);
}

TEST(NewtonWatchdog, LeavesAConvergingSolveAsItIs) {
  AtanProblem p;
  p.b = 0.2;
  Vec a = Vec::Constant(1, 0.5), b = a;
  const NewtonResult off = newton_solve(p.system(), settings(0), a);
  const NewtonResult on = newton_solve(p.system(), settings(2), b);
  ASSERT_TRUE(off.converged);
  ASSERT_TRUE(on.converged);
  EXPECT_FALSE(on.watchdog);
  EXPECT_EQ(on.iterations, off.iterations);
  EXPECT_EQ(a[0], b[0]);
}

TEST(NewtonWatchdog, OnlyWithAnAnchoredMerit) {
  // Without an anchor the merit does not move between iterates: the
  // watchdog has nothing to guard (a potential's Armijo search cannot cycle).
  AtanProblem p;
  p.b = 0.2;
  NewtonSystem sys = p.system();
  sys.anchor = nullptr;
  sys.energy = nullptr;  // the residual's own line search
  Vec u = Vec::Constant(1, 3.0);
  const NewtonResult r = newton_solve(sys, settings(6), u);
  EXPECT_FALSE(r.watchdog);
}

}  // namespace
}  // namespace rpfem
