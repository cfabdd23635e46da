// A scene as the case file declares it, after validation: bodies, their
// materials, meshes and boundary conditions, symmetry planes, solver and
// stepping settings. Contact is described by the formulation's own section,
// kept here unparsed for the formulation factory. Defaults: docs/case-format.md.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "fem/dof_map.hpp"
#include "geometry/die.hpp"
#include "la/linear_solver.hpp"
#include "material/flow_stress.hpp"
#include "mesh/mesh.hpp"
#include "solver/newton.hpp"

namespace rpfem {

// Prescribed velocity on the nodes of a boundary side; an absent component
// is free (a platen that slides), both given is a glued platen.
struct VelocityGroup {
  std::string name;   // used for the load columns of history.csv
  std::string body;
  std::string side;   // "<body>.<side>"
  std::optional<double> vx, vy;  // mm/s
};

// Surface traction on a side: pressure (MPa, positive pushes into the body)
// along the current normal, plus a fixed vector (tx, ty) in MPa.
struct TractionLoad {
  std::string side;
  double pressure = 0;
  Vec2 t = Vec2::Zero();
};

struct SymmetryPlane {
  int axis = 1;     // plane normal: 0 = x (r), 1 = y (z)
  double at = 0.0;  // mm
};

// Which boundary sides of a body may touch what: a rigid die (die set), or
// the sides of another body (with_body set; the friction of that interface
// in `friction`, a die's own is in Die::friction).
struct ContactPair {
  std::string body;
  std::vector<std::string> sides;  // "<body>.<side>"
  std::string die;
  std::string with_body;
  std::vector<std::string> with_sides;
  FrictionLaw friction;
  // Indices resolved by the reader: into Scene::bodies (= mesh body ids)
  // and Scene::dies; die_id < 0 for a pair of bodies.
  int body_id = -1, with_body_id = -1, die_id = -1;
  bool with_die() const { return die_id >= 0; }
};

struct BodySpec {
  std::string name;
  FlowStressLaw law;
  std::string material_name;
  std::optional<double> alpha_relative;  // replaces SolverSpec::alpha_relative for this body
};

struct SolverSpec {
  double alpha_relative = 1e5;        // alpha = alpha_relative * sigma_ref / rate_ref
  double limit_rate_relative = 1e-3;  // epsdot_lim = limit_rate_relative * rate_ref
  double regularization = 0;          // viscous regularization, relative to sigma_y / rate_ref
  NewtonSettings newton;
  LinearSolverChoice linear_solver = LinearSolverChoice::Auto;
  CholeskyMode cholesky = CholeskyMode::Supernodal;
  LuMode lu = LuMode::Auto;
  // Threads of the element loops (model/element_loop.hpp); the results do
  // not depend on it, bit for bit.
  int threads = 1;
  // Threads of the BLAS under the sparse factorizations (OpenBLAS's own
  // pool; a BLAS without threads ignores it). One by default: with
  // OpenBLAS the results change with its thread count (upsetting at 60 x 60
  // differs from the 10th digit between one thread and two), so they would
  // depend on the machine's cores; and `suite` and `sweep` already run one
  // job per core.
  int blas_threads = 1;
};

enum class TimeIntegration { Euler, Midpoint };

struct SteppingSpec {
  double stroke_increment = 0.1;  // mm per step of the reference motion
  // A step's increment grows with the stroke done: max(stroke_increment,
  // relative_increment * stroke) (0: fixed steps). For a stiff mode whose
  // stable step grows with the stroke, e.g. two bodies in series sharing a
  // stroke: their split relaxes at (d ln F / ds) / m per mm of stroke, an
  // explicit update is stable below ds (d ln F / ds) / m = 2, and a sphere's
  // load grows as its contact area, F ~ s (docs/theory.md, "Limits").
  double relative_increment = 0;
  double end_stroke = 1.0;        // mm
  std::string reference;          // velocity group (or die) whose travel is the stroke
  int max_cuts = 6;               // halvings of a failing step
  int output_every = 1;           // fields written every k steps (and the last)
  TimeIntegration integration = TimeIntegration::Euler;
  // Step control by a local error estimate (model/step_control.hpp): the
  // run's relative error bound over the stroke (0: off, fixed increments);
  // stroke_increment is then the first step's increment, and the control
  // keeps the increments within [min_increment, max_increment] (mm).
  double tolerance = 0;
  double min_increment = 0, max_increment = 0;
  // The nominal increment of the step that starts at this stroke, mm.
  double increment_at(double stroke) const { return std::max(stroke_increment, relative_increment * stroke); }
  // Steps at the nominal increments (a last short step counts as one).
  double planned_steps_real() const {
    if (relative_increment <= 0) return std::ceil(end_stroke / stroke_increment - 1e-9);
    // Fixed steps up to where the relative increment takes over, then a
    // geometric series: s_(k+1) = (1 + r) s_k.
    const double s1 = std::min(end_stroke, stroke_increment / relative_increment);
    const double fixed = std::ceil(s1 / stroke_increment - 1e-9);
    if (end_stroke <= fixed * stroke_increment + 1e-12) return fixed;
    const double from = std::max(fixed * stroke_increment, s1);
    return fixed + std::ceil(std::log(end_stroke / from) / std::log1p(relative_increment) - 1e-9);
  }
  int planned_steps() const { return std::max(1, static_cast<int>(std::min(planned_steps_real(), 2e9))); }
};

// [remesh]: when a run meshes its bodies anew (src/model/remesh.hpp; the
// driver does it, the stepper only stops for it). Off unless asked.
struct RemeshSpec {
  bool enabled = false;
  // After a step whose least scaled Jacobian is below this; and instead
  // of halving a step in which an element inverts (the last configuration
  // is remeshed).
  double min_scaled_jacobian = 0.3;
  // A step that would take the least scaled Jacobian below this is
  // rejected and the last configuration remeshed (on a fresh mesh: the
  // step halved).
  double reject_below = 0.2;
  double stroke_interval = 0;  // mm since the last remesh (0: never)
  // After a step in which a die's corner reaches deeper into a body than
  // this share of the target element size there (size times
  // die_corner_size; model/die_interference.hpp; 0: never).
  double die_interference = 1.0 / 3;
  double element_size = 0;     // mm (0: each body's mean initial edge length)
  double die_corner_size = 0.25;  // share of element_size at a die's corner near the body (1: uniform)
  int max_remeshes = 100;      // then the run stops
  // Share of a body's volume the simplification of its outline may change
  // per remesh (mesh/outline_mesher.hpp, OutlineOptions).
  double volume_tolerance = 1e-8;
  // Mesh the bodies with the remesher before the first step (its size
  // field graded at the dies' corners): the first remesh then meets the
  // resolution it makes, not the case's uniform mesh.
  bool initial_mesh = false;
  // The size from the old mesh's strain-rate error at this target relative
  // error (model/error_size_field.hpp; 0: off), bounded to min_size to
  // max_size times the body's size (below).
  double target_error = 0;
  double min_size = 0.2, max_size = 2;
  std::vector<int> bodies;  // the bodies meshed anew (remesh.bodies; default: all but virtual rigid ones)
  // mm, per body: the target element size, element_size or else the body's
  // mean edge length on the initial mesh (resolved by the reader; a remeshed
  // scene keeps it).
  std::vector<double> size;
};

struct Scene {
  std::string name;
  std::string file;
  std::string description;
  Geometry geometry = Geometry::Axisymmetric;
  Mesh mesh;  // all bodies, as generated
  std::vector<BodySpec> bodies;
  std::vector<VelocityGroup> velocities;
  std::vector<TractionLoad> tractions;
  std::vector<SymmetryPlane> symmetry;
  std::vector<Die> dies;
  std::vector<ContactPair> contact_pairs;
  SolverSpec solver;
  SteppingSpec stepping;
  RemeshSpec remesh;
  std::string formulation = "none";  // default contact formulation of the scene
  // run.suite_formulations: the ones `rpfem suite` runs here (empty: every
  // one that treats the scene's contacts).
  std::vector<std::string> suite_formulations;
  // Largest penetration over the local element size the run accepts
  // without a warning (run.penetration_tolerance).
  double penetration_tolerance = 1e-3;
  // Least scaled Jacobian a run without remeshing accepts without a
  // warning (run.min_scaled_jacobian).
  double min_scaled_jacobian = 0.1;
  // The most elements and nodes over all bodies (run.max_elements,
  // run.max_nodes): the case's meshes are checked as they are read, a
  // remesh's as it is made (model/remesh.hpp).
  Index max_elements = 2000000, max_nodes = 2500000;

  // The largest prescribed speed (dies and velocity groups), mm/s.
  double largest_speed() const {
    double v = 0;
    for (const Die& d : dies) v = std::max(v, d.motion.max_speed());
    for (const auto& g : velocities) v = std::max(v, Vec2(g.vx.value_or(0), g.vy.value_or(0)).norm());
    return v;
  }
};

}  // namespace rpfem
