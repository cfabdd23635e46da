// Newton-Raphson with a backtracking line search, reused by composition
// (after DOLFINx's NewtonSolver): the caller hands in callbacks for the
// functional, the residual/tangent assembly and the linear solve.
//
// Iteration k solves K du = -R. The first `direct_iterations` use the secant
// matrix (direct iteration, Kobayashi, Oh, Altan 1989, sec. 6.6) so Newton
// starts from a usable field; so does the iteration after one whose line
// search had to cut the step (`secant_after_cut`): far from the solution the
// consistent tangent of a rigid-plastic functional is nearly singular along
// the plastic flow (sigma_y epsdot is homogeneous of degree 1 in epsdot) and
// its steps overshoot many times over. The step length s halves until
//   Pi(u + s du) <= Pi(u) + c s R.du   (Armijo, when a potential or an
//                                       anchored merit exists and R.du < 0;
//                                       within round-off of Pi(u), a drop of
//                                       |R| is accepted instead), or
//   |R(u + s du)| <= (1 - c s) |R(u)|   (otherwise).
// Converged when |R| <= tol_force F_scale and the error left in u is at most
// tol_velocity |u|: that error is the next correction, estimated as theta
// |du| from the contraction theta = |du_k| / |du_k-1| < 1/2 of two
// successive full Newton steps (Deuflhard 2004, sec. 2.1), else |du| itself.
// A merit anchored at each iterate (NewtonSystem::anchor: Coulomb friction
// with its bound frozen there) is a different function at every iterate,
// so steps that each descend their own merit may cycle (core_in_sleeve
// under penalty: five iterates repeating to four digits, |R| 8.6e-3 to
// 1.3 of the force scale). With `watchdog` > 0, once |R| has not halved
// in that many iterations the search goes back to the iterate of least
// |R| so far and judges every step after by |R| itself (the second rule
// above), a merit that does not move and cannot cycle (the watchdog
// technique: Chamberlain, Powell, Lemarechal and Pedersen, Math. Prog.
// Study 16, 1982; Nocedal and Wright 2006, sec. 15.6). Slower than the
// anchored merit where that converges, and no surer from the start (by
// |R| in every solve core_in_sleeve under penalty with mortar rows
// stopped at 4.93 mm after 3,748 iterations; with the watchdog on its
// retries it finishes in 3,473), so it is a retry's (model/stepper.hpp),
// not every solve's.
// With a held factorization (reuse_factorization) the first iterations are
// the chord method (the simplified Newton method, Deuflhard 2004, sec.
// 2.1.4), linear in theta: its error is bounded by theta / (1 - theta) |du|.
#pragma once
#include <functional>
#include <string>

#include "core/types.hpp"

namespace rpfem {

// The round-off floor: when Newton's own correction is at machine precision
// (|du| / |u| below kRoundOffCorrection) no iteration can change u any more,
// and the residual left is the round-off of the largest terms that cancel
// in it (a virtual rigid body's viscosity, 1e4 times the work's, leaves
// about 1e-6 of the work's forces). Such a solve is accepted if that floor
// is within kRoundOffFactor of tol_force; the residual is reported as is.
// Shared by the step solvers that iterate themselves (formulations/ssn).
inline constexpr double kRoundOffCorrection = 1e-12;
inline constexpr double kRoundOffFactor = 100;
// Energy (or merit) differences below this fraction of |Pi| are round-off.
inline constexpr double kRoundOffEnergy = 1e-12;

struct NewtonSettings {
  double tol_velocity = 1e-8;
  double tol_force = 1e-7;
  int max_iterations = 40;
  int direct_iterations = 1;      // at the start of each solve
  bool secant_after_cut = true;   // a secant iteration after a cut line search
  // Start with the factorization held from the last solve (a re-solve after
  // a small change of the right-hand side, e.g. the augmented Lagrangian's
  // multipliers): the chord method while it contracts by at most
  // kFrozenContraction per iteration and its line search takes full steps.
  bool reuse_factorization = false;
  double armijo = 1e-4;
  int max_halvings = 12;
  // > 0: the watchdog above, after this many iterations without |R|
  // halving (only with an anchored merit); 0: off.
  int watchdog = 0;
};

struct NewtonSystem {
  // Pi(u); empty when the problem has no potential (residual line search).
  std::function<double(const Vec& u)> energy;
  // Set when energy is a merit anchored at an iterate (a potential whose
  // gradient there is R, e.g. Coulomb friction with its bound frozen):
  // called at u before each line search, which then uses energy.
  std::function<void(const Vec& u)> anchor;
  // Residual R(u) and the force scale used for the relative residual.
  std::function<void(const Vec& u, Vec& R, double& force_scale)> residual;
  // Optional: residual and energy in one pass (the same values as the two
  // calls), returning Pi(u); the line search's trials use it.
  std::function<double(const Vec& u, Vec& R, double& force_scale)> residual_energy;
  // Assembles the tangent at u (secant if !consistent), factorizes it and
  // solves K du = -R into du; false if the factorization failed.
  std::function<bool(const Vec& u, bool consistent, const Vec& R, Vec& du)> solve;
  // Solves K du = -R with the factorization of the last solve (of this or
  // an earlier solve of the same system); false if none is held. Optional.
  std::function<bool(const Vec& R, Vec& du)> reuse;
  // While on, residual evaluations also prepare a consistent tangent at
  // their u (one element pass for both; the same bits). Optional: Newton
  // turns it on for a full step's trial when the next iteration would
  // assemble the consistent tangent there.
  std::function<void(bool on)> keep_tangent;
};

struct NewtonResult {
  bool converged = false;
  int iterations = 0;
  int halvings = 0;            // line-search step cuts in total
  double residual = 0;         // |R| / F_scale at exit
  double correction = 0;       // |du| / |u| of the last iteration
  bool at_round_off = false;   // converged on the round-off floor (see newton.cpp)
  bool watchdog = false;       // the watchdog took over the line search
  // Not converged, and the last Newton correction was at round-off with
  // the residual above what is accepted there: the residual's round-off
  // floor lies above tol_force (an ill-conditioned problem).
  bool stalled = false;
  std::string reason;          // why it stopped when not converged
};

NewtonResult newton_solve(const NewtonSystem& sys, const NewtonSettings& s, Vec& u);

}  // namespace rpfem
