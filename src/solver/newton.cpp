#include "solver/newton.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rpfem {

namespace {
// The chord method (a held factorization) is kept while the corrections
// shrink at least this fast; beyond it Newton's fresh tangents are cheaper.
constexpr double kFrozenContraction = 0.25;
}  // namespace

NewtonResult newton_solve(const NewtonSystem& sys, const NewtonSettings& s, Vec& u) {
  NewtonResult out;
  Vec R, du, Rtrial;
  double scale = 1.0;
  sys.residual(u, R, scale);
  if (!(scale > 0) || !std::isfinite(scale)) scale = 1.0;
  // An anchored merit is evaluated after anchoring, at each line search.
  double energy = sys.energy && !sys.anchor ? sys.energy(u) : 0.0;
  double last_full = -1;  // |du| / |u| of the previous full Newton step; -1: none
  bool cut = false;       // the previous line search cut the step
  bool chord = s.reuse_factorization && sys.reuse;  // the held factorization is still used
  double last_chord = -1;  // |du| / |u| of the previous chord step; -1: none
  // The watchdog (newton.hpp): the iteration |R| last halved at, and the
  // iterate of least |R| so far.
  const bool watch = s.watchdog > 0 && sys.anchor && sys.energy;
  double halved_from = R.norm();
  int halved_at = 0;
  Vec least_u, least_R;
  double least_norm = R.norm(), least_scale = scale;
  if (watch) least_u = u, least_R = R;
  for (int it = 1; it <= s.max_iterations; ++it) {
    out.iterations = it;
    out.stalled = false;  // of the last iteration only
    const double rnorm = R.norm();
    if (!std::isfinite(rnorm)) {
      out.reason = "residual is not finite";
      return out;
    }
    const bool secant = it <= s.direct_iterations || (s.secant_after_cut && cut);
    const bool frozen = chord && sys.reuse(R, du);
    chord = frozen;
    if (!frozen && !sys.solve(u, !secant, R, du)) {
      out.reason = "tangent matrix is singular";
      return out;
    }
    if (!du.allFinite()) {
      out.reason = "correction is not finite";
      return out;
    }
    const double newton_correction = du.norm() / std::max(u.norm(), 1e-300);
    // Line search.
    if (sys.anchor) {
      sys.anchor(u);
      energy = sys.energy(u);
    }
    const double slope = R.dot(du);
    const bool use_energy = sys.energy && slope < 0 && !out.watchdog;
    double step = 1.0;
    Vec trial;
    double trial_energy = 0, trial_scale = scale;
    bool accepted = false;
    // Accepted, the full step is the next iterate, whose tangent is the
    // consistent one (no cut) unless the direct iterations go on; none
    // follows at the iteration limit, or where the full step meets
    // tol_velocity by the error estimate below (theta |du| of two full
    // Newton steps): only otherwise does its trial keep the tangent terms.
    const bool meets_tol = !frozen && !secant && last_full > 0 && newton_correction < 0.5 * last_full &&
                           newton_correction / last_full * newton_correction <= s.tol_velocity;
    const bool keep_full_step = sys.keep_tangent && it + 1 > s.direct_iterations && it < s.max_iterations && !meets_tol;
    for (int h = 0; h <= s.max_halvings; ++h) {
      trial = u + step * du;
      const bool keep = keep_full_step && h == 0;
      if (keep) sys.keep_tangent(true);
      if (!use_energy)
        sys.residual(trial, Rtrial, trial_scale);
      else if (sys.residual_energy)
        trial_energy = sys.residual_energy(trial, Rtrial, trial_scale);
      else
        sys.residual(trial, Rtrial, trial_scale), trial_energy = sys.energy(trial);
      if (keep) sys.keep_tangent(false);
      if (use_energy) {
        accepted = std::isfinite(trial_energy) && trial_energy <= energy + s.armijo * step * slope;
        // Energy changes at round-off (a converging virtual rigid body's
        // terms cancel to 1e-16 of Pi): the residual decides.
        if (!accepted && std::isfinite(trial_energy) &&
            trial_energy - energy <= kRoundOffEnergy * std::abs(energy) && Rtrial.allFinite())
          accepted = Rtrial.norm() <= (1.0 - s.armijo * step) * rnorm;
      } else {
        accepted = Rtrial.allFinite() && Rtrial.norm() <= (1.0 - s.armijo * step) * rnorm;
      }
      if (accepted) break;
      step *= 0.5;
      ++out.halvings;
    }
    if (!accepted) {
      // Take the smallest step anyway if it is finite: convergence is still
      // judged by the criteria below and the iteration limit.
      if (!Rtrial.allFinite()) {
        out.reason = "line search produced a non-finite residual";
        return out;
      }
    }
    cut = step < 1.0;
    // The chord method's contraction theta, and its end (a cut step, or
    // corrections that shrink too slowly).
    double theta = -1;
    if (frozen && last_chord > 0) theta = newton_correction / last_chord;
    if (frozen && (cut || theta > kFrozenContraction)) chord = false;
    last_chord = chord ? newton_correction : -1;
    u = trial;
    R = Rtrial;
    if (trial_scale > 0 && std::isfinite(trial_scale)) scale = trial_scale;
    if (use_energy) energy = trial_energy;
    else if (sys.energy && !sys.anchor) energy = sys.energy(u);
    if (watch && !out.watchdog) {
      const double n = R.norm();
      if (n < 0.5 * halved_from) halved_from = n, halved_at = it;
      if (n < least_norm) least_norm = n, least_u = u, least_R = R, least_scale = scale;
      if (it - halved_at >= s.watchdog) {
        // Back to the least |R| and judged by |R| from here on; the error
        // estimate starts again (no full step before).
        out.watchdog = true;
        u = least_u, R = least_R, scale = least_scale;
        last_full = -1, chord = false;
        continue;
      }
    }
    out.correction = step * du.norm() / std::max(u.norm(), 1e-300);
    out.residual = R.norm() / scale;
    // The error left in u: the next correction, theta times this one for a
    // contraction theta of two full Newton steps (a linear bound; the
    // quadratic rate makes it smaller), else this correction.
    const bool full_newton = !frozen && !secant && !cut;
    double error = out.correction;
    if (full_newton && last_full > 0 && newton_correction < 0.5 * last_full)
      error = std::min(error, newton_correction / last_full * out.correction);
    if (frozen && !cut && theta >= 0 && theta < 0.5) error = std::min(error, theta / (1 - theta) * out.correction);
    last_full = full_newton ? newton_correction : -1;
    if (it > s.direct_iterations && error <= s.tol_velocity && out.residual <= s.tol_force) {
      out.converged = true;
      return out;
    }
    out.stalled = it > s.direct_iterations && newton_correction <= kRoundOffCorrection;
    if (out.stalled && out.residual <= kRoundOffFactor * s.tol_force) {
      out.converged = out.at_round_off = true;
      out.stalled = false;
      return out;
    }
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "no convergence in %d iterations (residual %.2g, correction %.2g)%s", s.max_iterations,
                out.residual, out.correction, out.stalled ? ", stalled at the residual's round-off floor" : "");
  out.reason = buf;
  return out;
}

}  // namespace rpfem
