// The one interface through which the kernel calls a contact formulation.
//
// Like MFEM's ConstrainedSolver, a formulation may act in three ways, and
// the kernel does not care which: add terms to the step's functional (penalty:
// energy, gradient, Hessian), add velocity constraints in nodal frames
// (direct: elimination), or take over the step's solve (ipopt). Whatever it
// does, contact_forces() hands the nodal contact forces out the same way.
// The kernel never names a concrete formulation: formulations/factory.hpp
// turns the keyword into an object.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fem/dof_map.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

class StepProblem;

// What a formulation sees of the step: the configuration is fixed for the
// step (updated Lagrangian), velocities are the unknowns.
struct StepView {
  const Mesh* mesh = nullptr;
  const std::vector<Vec2>* x = nullptr;             // current node coordinates, mm
  // The configuration the solved velocity will move the nodes from, over
  // dt: x itself, except in the midpoint scheme's half-step solve, whose
  // velocity moves the nodes from the start of the step.
  const std::vector<Vec2>* x_from = nullptr;
  double time_from = 0;  // s, the time of x_from
  // Whether the solved velocity moves the nodes over dt. false: the solve
  // gives the instantaneous field at x, recorded, and in the midpoint
  // scheme only the predictor of the next half step (the end-of-step
  // solve): a formulation then anticipates no contact within dt.
  bool moves = true;
  const std::vector<double>* flow_stress = nullptr;  // per element, MPa (last solve)
  Geometry geometry = Geometry::Axisymmetric;
  double time = 0;  // s, at the start of the step
  double dt = 0;    // s
  int step = 0;
};

// Receives the contact terms at nodal velocities: the term's energy
// (N mm/s), gradient (2k, N) and Hessian (2k x 2k column-major, N s/mm) in
// global x/y components of nodes[0..k). A sink may ignore what it does not need.
class TermSink {
 public:
  virtual ~TermSink() = default;
  virtual void add(const Index* nodes, int k, double energy, const double* grad, const double* hess) = 0;
  // False when the sink uses energy or gradient only: a term may then skip
  // its Hessian (hess is not read).
  virtual bool needs_hessian() const { return true; }
};

struct TangentKind {
  bool symmetric = true;  // false: UMFPACK (frictional tangents)
  bool potential = true;  // false: the terms' gradient is not the energy's
  // Not a potential, but the formulation can anchor a merit at an iterate
  // (anchor_merit): the line search then uses it instead of the residual norm.
  bool merit = false;
};

// Outcome of a formulation that solved the step itself.
struct SolveOutcome {
  bool converged = false;
  int iterations = 0;
  double residual = 0;
  std::string reason;
};

// Verdict after a converged solve.
struct StepCheck {
  bool resolve = false;                 // contact state changed: solve again
  std::vector<std::string> events;      // touches, releases (logged per step)
};

struct NamedValue {
  std::string name;
  double value = 0;
};

class ContactFormulation {
 public:
  virtual ~ContactFormulation() = default;
  virtual std::string name() const = 0;

  // Start of a step (configuration fixed): contact search, active set.
  virtual void begin_step(const StepView&) {}
  // Velocity constraints in nodal frames, added to the kernel's own.
  virtual void constraints(const StepView&, std::vector<NodeConstraint>&) const {}
  // Node groups coupled by contact terms (the sparsity pattern).
  virtual void couplings(const StepView&, std::vector<std::vector<Index>>&) const {}
  // Contact terms of the functional at nodal velocities v.
  virtual void add_terms(const StepView&, const std::vector<Vec2>& v, TermSink&) const {}
  virtual TangentKind tangent() const { return {}; }
  // Non-potential terms (tangent().merit): freeze what makes them so at the
  // velocities v (Coulomb's friction bound, a function of the normal force)
  // until the next call. add_terms' energy is then a potential whose
  // gradient at v is the terms' gradient, the Newton line search's merit;
  // gradient and Hessian stay the live, consistent ones.
  virtual void anchor_merit(const StepView&, const std::vector<Vec2>& v) {}
  // A formulation that solves the step itself returns its outcome; u holds
  // the reduced unknowns on entry (initial guess) and on exit.
  virtual std::optional<SolveOutcome> solve(const StepView&, StepProblem&, Vec& u) { return std::nullopt; }
  // After a converged solve, with nodal velocities v and nodal forces F
  // (internal minus external: the reactions at constrained nodes).
  virtual StepCheck check(const StepView&, const std::vector<Vec2>& v, const std::vector<Vec2>& F) {
    return {};
  }
  // Largest step (s) before the motion v makes a contact event (a free node
  // reaching a die); the stepper shortens the step to it.
  virtual std::optional<double> limit_dt(const StepView&, const std::vector<Vec2>& v) const {
    return std::nullopt;
  }
  // Speed (mm/s) of a named object of the formulation (a die), so a die can
  // be the stroke reference; nullopt if the name is not the formulation's.
  virtual std::optional<double> reference_speed(const std::string& name) const { return std::nullopt; }
  // Nodal contact forces on the bodies (N), whichever way they arose.
  virtual void contact_forces(const StepView&, const std::vector<Vec2>& v, const std::vector<Vec2>& F,
                              std::vector<Vec2>& out) const {
    out.assign(v.size(), Vec2::Zero());
  }
  // Loads on the formulation's own objects (dies), N: names fixed at start.
  virtual std::vector<std::string> load_names() const { return {}; }
  virtual std::vector<Vec2> loads(const StepView&, const std::vector<Vec2>& F) const { return {}; }
  // Per-node fields of the last converged solve for result.h5 (e.g. the
  // contact pressure and shear stress, MPa); zero away from contact.
  virtual void node_fields(const StepView&, std::map<std::string, std::vector<double>>& out) const {}
  // Values the formulation derived from the scene (defaults it scaled, e.g.
  // a penalty parameter), recorded in the run's summary.
  virtual std::vector<NamedValue> derived() const { return {}; }
  // Largest penetration of the last solve's configuration over the local
  // element size (the run warns above run.penetration_tolerance); nullopt
  // if the formulation measures none (`direct` places its nodes on the dies).
  virtual std::optional<double> max_penetration_rel() const { return std::nullopt; }
  // Per-step scalars for history.csv (names fixed at start).
  virtual std::vector<std::string> report_names() const { return {}; }
  virtual std::vector<double> report() const { return {}; }
  // After the nodes moved to x (the configuration at view.time + view.dt),
  // a formulation may place its contact nodes back on curved surfaces they
  // slid along (ALPID's correction); returns the largest move (mm).
  virtual double place_on_surfaces(const StepView&, std::vector<Vec2>& x) { return 0; }
  // End of an accepted step of length dt: move dies, carry contact state.
  virtual void advance(const StepView&, const std::vector<Vec2>& v) {}
};

}  // namespace rpfem
