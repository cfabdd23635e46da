// The one interface through which the kernel calls a contact treatment.
//
// Like MFEM's ConstrainedSolver, a treatment may act in three ways, and the
// kernel does not care which: add terms to the step's functional (penalty,
// augmented Lagrangian: energy, gradient, Hessian), add velocity
// constraints in nodal frames (direct: elimination), or solve the step with
// its own solver (ipopt: a StepSolver). Whatever it does, record() hands
// the contact forces, die loads and fields out the same way. The kernel
// never names a concrete treatment: formulations/factory.hpp builds one
// from an enforcement and a discretization (src/contact/contact_model.hpp).
#pragma once
#include <any>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fem/dof_map.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

class StepProblem;

// What a treatment sees of the step: the configuration is fixed for the
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
  // solve): contact then anticipates no landing within dt.
  bool moves = true;
  // Whether contact anticipates a landing within dt (with moves). false:
  // of the slaves that land (not mortar's gradual rows), only those
  // touching now take part, and landing control ends the step where the
  // solved velocity lands another (the start of an Euler step under step
  // control, whose length is chosen after the solve).
  bool anticipates = true;
  // The velocity the solve starts from (the last solve's: the step's
  // predicted motion), indexed like x; null, or all zero, before any solve.
  // A treatment may look ahead with it: the rows a slave approaching
  // within the step will need (formulations/mortar/mortar.hpp).
  const std::vector<Vec2>* velocity = nullptr;
  const std::vector<double>* flow_stress = nullptr;  // per element, MPa (last solve)
  Geometry geometry = Geometry::Axisymmetric;
  double time = 0;  // s, at the start of the step
  double dt = 0;    // s
  int step = 0;
  // Whether landing control shortened the step to end where a slave lands
  // (model/stepper.cpp). A treatment that finds a landing row with no
  // solution there (at zero gap and zero force its friction lifts it off,
  // free it penetrates) may fail the solve at once: the stepper then tries
  // the step past the landing, where the row presses.
  bool at_landing = false;
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
  // The elements' nodal force at `node` (internal minus external, before
  // any contact term): at a node held by constraints, the reaction they
  // carry. Known for the nodes the treatment named in force_nodes() (zero
  // for the others, and in an energy sink). A term may depend on it:
  // Coulomb's bound mu N on a node held on a die (N = n . F).
  virtual Vec2 element_force(Index node) const { return Vec2::Zero(); }
  // Tangent sinks: adds the outer product of coef (2k values: the x, y
  // components at nodes[0..k)) with the derivative of dir . element_force
  // (node) by all velocities (dir^T times the elements' Hessian rows of
  // `node`): the linearization of a term's dependence on that force.
  virtual void add_force_coupling(Index node, const Vec2& dir, const Index* nodes, int k, const double* coef) {}
};

struct TangentKind {
  bool symmetric = true;  // false: UMFPACK (frictional tangents)
  bool potential = true;  // false: the terms' gradient is not the energy's
  // Not a potential, but the treatment can anchor a merit at an iterate
  // (anchor_merit): the line search then uses it instead of the residual norm.
  bool merit = false;
  // > 0: the treatment measures its constraints from the velocities (an
  // augmented Lagrangian's gaps) and needs Newton's velocity error below
  // this (relative); the tighter of it and solver.tol_velocity is used.
  double tol_velocity = 0;
};

// Outcome of a step solved by a treatment's own solver.
struct SolveOutcome {
  bool converged = false;
  int iterations = 0;
  double residual = 0;
  std::string reason;
};

// A step solver other than the kernel's Newton (MFEM's ConstrainedSolver
// subclasses): u holds the reduced unknowns on entry (initial guess) and on
// exit.
class StepSolver {
 public:
  virtual ~StepSolver() = default;
  virtual SolveOutcome solve(const StepView&, StepProblem&, Vec& u) = 0;
};

// Verdict after a converged solve.
struct StepCheck {
  bool resolve = false;                 // contact state changed: solve again
  // The change is small (multipliers only: the terms' Hessian is the same
  // but for rows crossing their kink): the next solve starts with the last
  // solve's factorization (the chord method, solver/newton.hpp) and then
  // Newton's consistent tangent, without the secant iterations meant for a
  // new configuration or a new contact state.
  bool warm = false;
  std::vector<std::string> events;      // touches, releases (logged per step)
};

struct NamedValue {
  std::string name;
  double value = 0;
};

// What a treatment reports of a converged solve, for the step's record.
struct ContactRecord {
  std::vector<Vec2> force;     // N per node: the contact force on the bodies
  std::vector<Vec2> loads;     // N per entry of ContactInfo::load_names
  std::vector<double> columns; // per entry of ContactInfo::column_names (history.csv)
  std::map<std::string, std::vector<double>> fields;  // per node (result.h5), zero away from contact
  // Largest penetration over the local element size (the run warns above
  // run.penetration_tolerance); nullopt if the treatment measures none.
  std::optional<double> penetration_rel;
  // An exact friction law's largest violation (relative: of a row's bound,
  // or a sticking row's slip over the speed scale); nullopt if the
  // treatment has no exact friction. The run warns above 1e-8
  // (RunHealth::kFrictionTolerance).
  std::optional<double> friction_violation;
  std::string friction_cause;  // the row behind it and why (empty: not named)
};

// What a treatment states once, at the start of a run.
struct ContactInfo {
  std::string enforcement, discretization;  // the two axes ("none" for none)
  std::vector<std::string> load_names;      // its dies
  std::vector<std::string> column_names;
  std::vector<NamedValue> derived;          // values derived from the scene (summary.json)
};

// Where bodies touch one another, handed from a treatment to the one that
// takes over after a remesh: per interface (by name), the segments of the
// surface in contact at the remesh's configuration (a lone node in contact:
// a segment of zero length). Positions, not nodes: the meshes differ.
struct ContactZones {
  std::map<std::string, std::vector<std::array<Vec2, 2>>> segments;
  // Per interface whose rows in contact were all one side's nodes: that
  // side (0: the pair's body, 1: its `with` body), the slave of one pass.
  std::map<std::string, int> slave_side;
  // Per interface (dies too): the forces of the rows in contact, per unit
  // of their lumped area, where their slave nodes stood. A treatment that
  // solves the forces as unknowns starts the new mesh's rows from them
  // (ContactRow::prior), as the velocities carried over start Newton.
  struct Traction {
    Vec2 at = Vec2::Zero();       // mm
    Vec2 tangent = Vec2::Zero();  // the row's t = (-n_y, n_x)
    double normal = 0;            // MPa, > 0 pressing
    double friction = 0;          // MPa, on the slave along `tangent`
    bool stick = false;
    // The enforcement's factor on the row's stiffness (the adaptive
    // penalty's, contact/adaptive_penalty.hpp): the new rows start from it
    // rather than from 1 (a row raised before the remesh presses as hard
    // after it and would be raised again).
    double row_factor = 1;
  };
  std::map<std::string, std::vector<Traction>> tractions;
};

class ContactFormulation {
 public:
  virtual ~ContactFormulation() = default;
  virtual ContactInfo info() const = 0;

  // Start of a solve of a configuration: contact search, rows, state.
  virtual void begin_step(const StepView&) {}
  // Velocity constraints in nodal frames, added to the kernel's own.
  virtual void constraints(const StepView&, std::vector<NodeConstraint>&) const {}
  // Node groups coupled by contact terms (the sparsity pattern).
  virtual void couplings(const StepView&, std::vector<std::vector<Index>>&) const {}
  // The nodes whose elements' force its terms read (TermSink::element_force).
  virtual void force_nodes(const StepView&, std::vector<Index>&) const {}
  // After a solve that failed: whether the treatment switched to a more
  // robust scheme for this solve (the stepper then solves it once more
  // from the same start, before it halves the step).
  virtual bool fall_back() { return false; }
  // Contact terms of the functional at nodal velocities v.
  virtual void add_terms(const StepView&, const std::vector<Vec2>& v, TermSink&) const {}
  virtual TangentKind tangent() const { return {}; }
  // Non-potential terms (tangent().merit): freeze what makes them so at the
  // velocities v (Coulomb's friction bound, a function of the normal force)
  // until the next call; add_terms' energy is then the line search's merit.
  virtual void anchor_merit(const StepView&, const std::vector<Vec2>& v) {}
  // The treatment's own step solver, or nullptr for the kernel's Newton.
  virtual StepSolver* solver() { return nullptr; }
  // After a converged solve, with nodal velocities v and nodal forces F
  // (internal minus external: the reactions at constrained nodes).
  virtual StepCheck settle(const StepView&, const std::vector<Vec2>& v, const std::vector<Vec2>& F) { return {}; }
  // Largest step (s) before the motion v lands a free node on its master;
  // the stepper shortens the step to it.
  virtual std::optional<double> limit_dt(const StepView&, const std::vector<Vec2>& v) const { return std::nullopt; }
  // Whether limit_dt ends a step at a free node's landing (the stepper's
  // start-of-step solves need not anticipate landings then:
  // StepView::anticipates).
  virtual bool controls_landings() const { return false; }
  // Landing control's correction from the step's end. Before a step's
  // attempts: the rows' gaps now are remembered (and the state a retune
  // starts from, below). After an attempt's end solve (its rows at the end
  // configuration): the fraction of the attempt to redo the step with,
  // where a row ended deeper than the treatment's tolerance allows
  // (ContactModel::overshoot). nullopt: none did.
  virtual void remember_start_gaps() {}
  virtual std::optional<double> overshoot() const { return std::nullopt; }
  // After an attempt's end solve, before overshoot(): whether the
  // treatment changed its own parameters for the step, so that the step is
  // solved again from its start at the same length (a penalty raised on
  // the rows that ended it deeper than run.penetration_tolerance); its
  // state is put back to where the step started (remember_start_gaps was
  // called there). What changed, for the log; nullopt: nothing did.
  virtual std::optional<std::string> retune() { return std::nullopt; }
  // After the nodes moved to x (the configuration at view.time + view.dt):
  // nodes held on curved die surfaces are placed back on them (ALPID's
  // correction); returns the largest move (mm).
  virtual double place_on_surfaces(const StepView&, std::vector<Vec2>& x) { return 0; }
  // End of an accepted step: contact state carried to the next.
  virtual void end_step(const StepView&, const std::vector<Vec2>& v) {}
  // The contact state a step's attempt changes (the rows in contact, the
  // multipliers, the roles, the pending events): saved before a step's
  // first attempt and restored after an attempt that is not kept (failed,
  // or redone shorter), so that every attempt starts from the state the
  // step started from. A treatment without state keeps the defaults.
  virtual std::any save_state() const { return {}; }
  virtual void restore_state(const std::any&) {}
  // At a remesh, on the old mesh's treatment: where bodies touch at x (the
  // last settled solve's contact state).
  virtual ContactZones contact_zones(const std::vector<Vec2>& x) const { return {}; }
  // On the new mesh's treatment, before its first step: the contact it
  // takes over (between bodies; nodes on dies are placed on them by the
  // remesh itself).
  virtual void take_over(const ContactZones&) {}
  // The last converged solve's forces, loads, fields and columns.
  virtual ContactRecord record(const StepView&, const std::vector<Vec2>& v, const std::vector<Vec2>& F) const {
    ContactRecord r;
    r.force.assign(v.size(), Vec2::Zero());
    return r;
  }
};

}  // namespace rpfem
