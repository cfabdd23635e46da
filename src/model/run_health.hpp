// What a run cannot vouch for, gathered over its recorded steps and said
// as warnings at its end (summary.json `warnings`; the run still writes
// every step): a tangent ill-conditioned or steps solved only to a
// residual floor far above solver.tol_force, step control's estimate kept
// above its bound, an exact friction law missed, penetration beyond
// run.penetration_tolerance, and, without remeshing, a mesh distorted
// below run.min_scaled_jacobian. Each warning names the worst step, its
// stroke and what to change.
#pragma once
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace rpfem {

class RunHealth {
 public:
  struct Limits {
    double tol_force = 1e-7;              // solver.tol_force
    double penetration_tolerance = 1e-3;  // run.penetration_tolerance
    double min_scaled_jacobian = 0.1;     // run.min_scaled_jacobian
    bool remeshing = false;               // remesh.enabled: distortion is the remesher's
  };
  // Steps whose exact friction law was violated beyond this (relative;
  // ContactRecord::friction_violation) are counted.
  static constexpr double kFrictionTolerance = 1e-8;
  // Steps solved to a residual above this factor times tol_force (an
  // order of magnitude above the tolerance asked for; Newton accepts up to
  // 100 times at round-off, solver/newton.cpp) are counted: measured,
  // alpha 1e10 leaves 5e-6 to 9e-6 at every step of upsetting, the virtual
  // rigid punch 1.1e-6 at its first solve, 1e-7 at the coarse mesh.
  static constexpr double kFloorWarning = 10;

  explicit RunHealth(Limits limits) : limits_(limits) {}

  // A recorded step's solve: its factorizations' least condition estimate
  // and its residual (relative to the force scale).
  void note_solve(int step, double rcond, double residual);
  // A recorded step's contact record: its friction violation (and the
  // enforcement's words for it) and penetration, where measured.
  void note_contact(int step, double stroke, std::optional<double> friction_violation, const std::string& cause,
                    std::optional<double> penetration_rel);
  // A recorded step's least scaled Jacobian and its element.
  void note_quality(int step, double stroke, double quality, Index element);
  // Step control: a kept step's local error estimate against its bound.
  void note_step_error(int step, double estimate, double bound);

  // The least condition estimate over the recorded steps (INFINITY: none).
  double min_rcond() const { return min_rcond_; }
  // The warnings; element_name names an element for the reader.
  std::vector<std::string> warnings(const std::function<std::string(Index)>& element_name) const;

 private:
  Limits limits_;
  double min_rcond_ = INFINITY;
  int min_rcond_step_ = -1, floor_steps_ = 0, worst_floor_step_ = -1;
  double worst_floor_ = 0;
  int steps_above_bound_ = 0, worst_bound_step_ = -1;
  double worst_bound_ratio_ = 0;
  int friction_steps_ = 0, worst_friction_step_ = -1;
  double worst_friction_ = 0, worst_friction_stroke_ = 0;
  std::string worst_friction_cause_;
  int penetrating_steps_ = 0, worst_penetration_step_ = -1;
  double worst_penetration_ = 0, worst_penetration_stroke_ = 0;
  int distorted_steps_ = 0, first_distorted_step_ = -1, worst_distorted_step_ = -1;
  Index first_distorted_element_ = -1, worst_distorted_element_ = -1;
  double first_distorted_ = 0, worst_distorted_ = INFINITY, first_distorted_stroke_ = 0, worst_distorted_stroke_ = 0;
};

}  // namespace rpfem
