#include "penalty/penalty_enforcement.hpp"

#include "contact/friction_treatment.hpp"

namespace rpfem {

namespace {

RegularizedSettings read_settings(const Scene& scene, CaseSection& s, const ContactDiscretization& disc) {
  RegularizedSettings r;
  const double size = scene.mesh.size();
  const double factor = s.real("beta_factor", 1.0, Range::positive(), "times the default beta");
  const auto beta = s.optional_real("beta", Range::positive(), "MPa s/mm (replaces the default)");
  r.beta_hat = default_beta_hat(scene, disc, factor, beta);
  r.gap_correction = s.flag("gap_correction", true);
  r.touch_tol = s.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  r.release_tol = s.real("release_tolerance", 1e-9, Range::nonnegative(), "relative to the largest contact force");
  r.speed_scale = scene.largest_speed();
  // The adaptive penalty (contact/adaptive_penalty.hpp): on unless the case
  // fixes beta (a beta_factor or beta given is the one used, as the
  // penalty-sensitivity studies need).
  r.adapt.on = s.flag("adapt", !(s.has("beta_factor") || s.has("beta")));
  r.adapt.max_factor = s.real("beta_max_factor", 1e3, Range{1.0, INFINITY, false, false},
                              "largest factor on a row's beta");
  r.adapt.tolerance = scene.penetration_tolerance;
  return r;
}

}  // namespace

PenaltyEnforcement::PenaltyEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc)
    : RegularizedEnforcement(disc, read_settings(scene, settings, disc)) {
  require_friction_treatment(scene, name(), {});
}

}  // namespace rpfem
