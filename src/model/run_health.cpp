#include "model/run_health.hpp"

#include "core/sci.hpp"
#include "la/linear_solver.hpp"

namespace rpfem {

void RunHealth::note_solve(int step, double rcond, double residual) {
  if (rcond < min_rcond_) min_rcond_ = rcond, min_rcond_step_ = step;
  if (residual > kFloorWarning * limits_.tol_force) {
    ++floor_steps_;
    if (residual > worst_floor_) worst_floor_ = residual, worst_floor_step_ = step;
  }
}

void RunHealth::note_contact(int step, double stroke, std::optional<double> friction_violation,
                             const std::string& cause, std::optional<double> penetration_rel) {
  if (const auto f = friction_violation; f && !(*f <= kFrictionTolerance)) {
    ++friction_steps_;
    if (!(*f <= worst_friction_))
      worst_friction_ = *f, worst_friction_step_ = step, worst_friction_stroke_ = stroke, worst_friction_cause_ = cause;
  }
  if (const auto pen = penetration_rel) {
    penetrating_steps_ += !(*pen <= limits_.penetration_tolerance);
    if (!(*pen <= worst_penetration_))
      worst_penetration_ = *pen, worst_penetration_step_ = step, worst_penetration_stroke_ = stroke;
  }
}

void RunHealth::note_quality(int step, double stroke, double quality, Index element) {
  if (limits_.remeshing || !(quality < limits_.min_scaled_jacobian)) return;
  if (distorted_steps_++ == 0)
    first_distorted_ = quality, first_distorted_step_ = step, first_distorted_element_ = element,
    first_distorted_stroke_ = stroke;
  if (quality < worst_distorted_)
    worst_distorted_ = quality, worst_distorted_step_ = step, worst_distorted_element_ = element,
    worst_distorted_stroke_ = stroke;
}

void RunHealth::note_step_error(int step, double estimate, double bound) {
  if (!(estimate > bound)) return;
  ++steps_above_bound_;
  if (estimate / bound > worst_bound_ratio_) worst_bound_ratio_ = estimate / bound, worst_bound_step_ = step;
}

std::vector<std::string> RunHealth::warnings(const std::function<std::string(Index)>& element_name) const {
  std::vector<std::string> out;
  if (min_rcond_ < kIllConditionedRcond || floor_steps_ > 0) {
    std::string w = "the tangent was ill-conditioned";
    if (std::isfinite(min_rcond_)) w += ": least rcond " + sci(min_rcond_) + " at step " + std::to_string(min_rcond_step_);
    if (min_rcond_ < kIllConditionedRcond) w += " (below 100 x machine epsilon)";
    if (floor_steps_ > 0)
      w += "; " + std::to_string(floor_steps_) + " step(s) solved only to the residual's round-off floor, up to " +
           sci(worst_floor_) + " at step " + std::to_string(worst_floor_step_) + " (solver.tol_force " +
           sci(limits_.tol_force) + ")";
    out.push_back(w + ": a penalty or stiffness too large for double precision");
  }
  if (steps_above_bound_ > 0)
    out.push_back("step control: " + std::to_string(steps_above_bound_) +
                  " step(s) kept at stepping.min_increment with the local error estimate above its bound, up to " +
                  sci(worst_bound_ratio_) + " times it at step " + std::to_string(worst_bound_step_) +
                  " (history.csv: step_error, step_error_bound): the run may miss stepping.tolerance; "
                  "lower stepping.min_increment");
  if (friction_steps_ > 0)
    out.push_back("exact friction met only to " + sci(worst_friction_) + " at step " +
                  std::to_string(worst_friction_step_) + " (stroke " + sci(worst_friction_stroke_) + " mm), above " +
                  sci(kFrictionTolerance) + " at " + std::to_string(friction_steps_) +
                  " step(s) (history.csv: kkt_friction, kkt_stick_slip): " +
                  (worst_friction_cause_.empty() ? "a row at the kink between stick and slip" : worst_friction_cause_) +
                  "; a smaller stepping.stroke_increment, or the arctan law (regularization = \"arctan\") "
                  "under another enforcement");
  if (penetrating_steps_ > 0)
    out.push_back("penetration unacceptable: " + sci(worst_penetration_) + " of the element size at step " +
                  std::to_string(worst_penetration_step_) + " (stroke " + sci(worst_penetration_stroke_) +
                  " mm), above run.penetration_tolerance = " + sci(limits_.penetration_tolerance) + " at " +
                  std::to_string(penetrating_steps_) +
                  " step(s); raise the contact penalty (formulations.penalty.beta_factor; under "
                  "formulations.penalty.adapt its beta_max_factor) or shorten the steps "
                  "(stepping.stroke_increment)");
  if (distorted_steps_ > 0) {
    // A mesh this distorted integrates its elements poorly (a corner angle
    // of asin(0.1) = 5.7 degrees at the default): the fields near the
    // element, and the loads, are doubtful.
    std::string w = "mesh distorted: least scaled Jacobian below run.min_scaled_jacobian = " +
                    sci(limits_.min_scaled_jacobian) + " from step " + std::to_string(first_distorted_step_) +
                    " (stroke " + sci(first_distorted_stroke_) + " mm, " + element_name(first_distorted_element_) +
                    ", " + sci(first_distorted_) + ")";
    if (worst_distorted_step_ != first_distorted_step_)
      w += ", down to " + sci(worst_distorted_) + " at step " + std::to_string(worst_distorted_step_) + " (stroke " +
           sci(worst_distorted_stroke_) + " mm, " + element_name(worst_distorted_element_) + ")";
    out.push_back(w + ", at " + std::to_string(distorted_steps_) +
                  " step(s) (history.csv: min_scaled_jacobian); remesh the bodies (a [remesh] table with "
                  "enabled = true)");
  }
  return out;
}

}  // namespace rpfem
