// Incremental quasi-static stepping, updated Lagrangian (Kobayashi, Oh,
// Altan 1989, sec. 6.7): on the current configuration solve the velocity
// field, then move the nodes by v dt and integrate the effective strain at
// the integration points, eps += epsdot dt. Step 0 is the solve on the
// initial configuration; every step records a configuration and the solution
// on it. A failing step (Newton divergence, an inverted element) is redone
// from the last accepted state, its contact state included
// (ContactFormulation::save_state), with half the step, up to max_cuts times;
// then the run stops, every finished step already recorded. The stop
// reason carries the failing solve's least tangent condition estimate, and
// says when it was ill-conditioned (la/linear_solver.hpp, solver/newton.hpp).
#pragma once
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

struct StepRecord {
  int step = 0;
  double time = 0, stroke = 0, dt = 0;  // s, mm, s (dt of the step that led here)
  int cuts = 0;                         // halvings needed to reach this step
  bool landing = false;                 // landing control ended the step where a node lands
  int newton_iterations = 0;            // incl. contact re-solves
  int contact_passes = 0;               // solves of this configuration
  int solves = 0;                       // all solves of the step (midpoint: the half step's too)
  double residual = 0;                  // relative force residual
  double tangent_rcond = -1;            // least condition estimate of the step's
                                        // factorizations (-1: none, e.g. ipopt)
  double step_error = 0;                // step control: the step's local error estimate
  double step_error_bound = 0;          // and its bound (model/step_control.hpp; 0: off)
  std::vector<Vec2> x, v;               // mm, mm/s
  std::vector<double> strain_rate, strain, mean_stress, flow_stress;  // per element
  // The recovery-based strain-rate error (mesh/error_indicator.hpp): per
  // element its root mean square (1/s), and the global relative estimate.
  std::vector<double> strain_rate_error;
  double strain_rate_error_relative = 0;
  std::vector<Vec2> loads;              // N, whole body, per load_names entry
  std::vector<Vec2> contact_force;      // N, per node
  std::vector<double> contact_report;   // per formulation report_names entry
  std::map<std::string, std::vector<double>> node_fields;  // per node, from the formulation
  std::vector<std::string> events;
  double volume = 0;                    // mm^3, whole body
  double min_scaled_jacobian = 0;
  int rigid_points = 0;                 // integration points below the limiting rate
};

// Values the run derived from the scene (recorded in the summary).
struct DerivedParameters {
  double reference_speed = 0;        // mm/s
  double reference_length = 0;       // mm
  double reference_strain_rate = 0;  // 1/s
  double limiting_strain_rate = 0;   // 1/s
  double regularization = 0;         // s
  std::vector<double> alpha;         // MPa s, per body
  double dt_nominal = 0;             // s
  double force_floor = 0;            // N, the least force scale of a residual
  std::vector<NamedValue> contact;   // the contact formulation's own
};

// The driver's side: it writes files and prints; the kernel does neither.
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual void on_start(const DerivedParameters&, const std::vector<std::string>& load_names,
                        const std::vector<std::string>& report_names) {}
  virtual void on_step(const StepRecord&) = 0;
  // A step tried again with dt (s): why the last attempt was not kept.
  virtual void on_retry(int step, double dt, const std::string& why) {}
  // The contact events of an attempt at a step that was not kept (failed,
  // or redone shorter); its contact state is undone (the next attempt
  // starts from the step's). Before the on_retry that follows it, if any.
  virtual void on_discarded(int step, const std::vector<std::string>& events) {}
  // A resumed run's first solve, at the configuration it resumes from (the
  // step on record already, after a remesh on its old mesh): not a step.
  virtual void on_resumed(const StepRecord&) {}
  // Whether the run should stop at the next step boundary (a signal the
  // driver caught): it then ends `interrupted`, its finished steps kept.
  virtual bool stop_requested() const { return false; }
};

// Where a run is: the last recorded configuration and its solution. A run
// on the same bodies resumes from it (run_scene's `from`): after a remesh,
// with the state moved onto the new mesh.
struct RunState {
  std::vector<Vec2> x;                        // mm
  std::vector<std::array<double, 4>> strain;  // effective strain at the 2x2 points
  std::vector<Vec2> v;                        // mm/s, the solution there (Newton's start on resuming)
  double time = 0, stroke = 0;                // s, mm
  int step = 0;                               // the step recorded there
  double dt = 0;  // s, that step's length: a resumed run's first solve takes it (0: the nominal step)
  // 1/s, the effective strain rate at the 2x2 points of the solution there
  // (the remesher's size field from its error, model/error_size_field.hpp;
  // empty: not solved, e.g. moved onto a new mesh).
  std::vector<std::array<double, 4>> rate;
};

struct RunOutcome {
  RunState last;  // the last recorded step's state
  bool finished = false;
  bool interrupted = false;  // stopped at a step boundary on StepObserver::stop_requested
  // Stopped for a remesh (scene.remesh): why; the driver remeshes `last`
  // and resumes. Empty otherwise.
  std::string remesh;
  std::string reason;  // why the run stopped early
  int steps = 0;       // recorded steps after step 0
  int total_newton_iterations = 0;  // of the kept steps' solves
  // Of the attempts not kept: failed, redone shorter, or solved again
  // with the treatment's parameters changed.
  int discarded_newton_iterations = 0;
  int total_cuts = 0;
  int step_rejections = 0;  // steps redone shorter by the step control (stepping.tolerance)
  // Steps solved again from their start with the contact treatment's
  // parameters changed (ContactFormulation::retune).
  int retunes = 0;
  double assembly_seconds = 0, analyze_seconds = 0, factor_seconds = 0, solve_seconds = 0;
  double residual_seconds = 0, contact_seconds = 0;  // model/step_problem.hpp's SolverWorkspace
  int pattern_builds = 0, factorizations = 0, cholesky_fallbacks = 0;
  int tangent_passes = 0, tangents_from_trials = 0;  // SolverWorkspace's
  int force_passes = 0, force_passes_reused = 0;     // SolverWorkspace's
  int by_cholmod = 0, by_klu = 0, by_umfpack = 0;  // la/linear_solver.hpp's LinearSolveStats
  double min_tangent_rcond = INFINITY;  // over the recorded steps
  // What the run met that makes its results doubtful, as sentences for the
  // driver to record and print (model/run_health.hpp).
  std::vector<std::string> warnings;
};

// Runs the scene to its end stroke, from its initial configuration or,
// given `from`, from that state (x and strain on scene.mesh): the run's
// first solve is then an instantaneous one there, not recorded (step
// from->step is on record already), and the steps go on from it.
RunOutcome run_scene(const Scene& scene, ContactFormulation& contact, StepObserver& observer,
                     const RunState* from = nullptr);

}  // namespace rpfem
