// One step's discrete problem on the fixed current configuration: the
// bodies' rigid-plastic functional (paper eq. 2) plus the contact
// formulation's terms, in the reduced unknowns u of the step's DofMap.
//
//   Pi(u) = sum_e Pi_e(v(u)) - F_ext . v(u) + Pi_contact(v(u))
//   R(u)  = T^T F(v),  F = dPi/dv (full nodal force; at a constrained node
//           its constrained components are the reactions)
#pragma once
#include <array>
#include <vector>

#include "core/timing.hpp"
#include "fem/dof_map.hpp"
#include "fem/rigid_plastic_element.hpp"
#include "la/linear_solver.hpp"
#include "la/sparse_assembler.hpp"
#include "model/contact_formulation.hpp"
#include "model/element_material.hpp"
#include "solver/newton.hpp"

namespace rpfem {

// Persists across steps so the pattern and symbolic factorization are reused.
struct SolverWorkspace {
  explicit SolverWorkspace(LinearSolverChoice c, CholeskyMode m = CholeskyMode::Supernodal, LuMode l = LuMode::Auto)
      : linear(c, m, l) {}
  SparseAssembler assembler;
  LinearSolver linear;
  DofMap dofs;
  std::vector<std::vector<Index>> couplings;
  std::uint64_t layout = 0;
  bool has_pattern = false;
  int pattern_builds = 0;
  // Tangents whose element terms were computed by tangent() itself, and
  // those scattered from a residual's kept terms (keep_tangent_terms).
  int tangent_passes = 0, tangents_from_trials = 0;
  // Element passes for forces (and energies) run, and those served by the
  // last one's results at the same velocities.
  int force_passes = 0, force_passes_reused = 0;
  // Counts the writes to `terms` and to the assembler's values (kept terms
  // are valid while it stands still).
  std::uint64_t terms_writes = 0;
  double assembly_seconds = 0;  // s: the elements' tangent, scattered into the matrix
  double residual_seconds = 0;  // s: the elements' forces and energies (residual, line search)
  double contact_seconds = 0;   // s: the contact's terms, rows and settling
  int threads = 1;                    // of the element loops
  std::vector<ElementTerms> terms;    // per element, the tangent's element terms
  std::vector<double> element_values; // per element, energies or squared force norms
  std::vector<Vec8> element_forces;   // per element, dPi_e/dv
};

class StepProblem {
 public:
  StepProblem(const StepView& view, const std::vector<std::array<double, 4>>& strain,
              const std::vector<ElementMaterial>& materials, double epsdot_lim,
              const std::vector<Vec2>& external_force, ContactFormulation& contact, SolverWorkspace& ws);

  // Installs the step's constraints (kernel's and formulation's) and the
  // formulation's couplings; rebuilds the pattern only if they changed.
  void set_constraints(const std::vector<NodeConstraint>& constraints);
  const DofMap& dofs() const { return ws_.dofs; }

  double energy(const Vec& u) const;
  // Full nodal force F = dPi/dv at nodal velocities v; returns a force scale
  // for relative residuals: the norm of the element forces, at least the
  // floor (set_force_floor).
  // With element_energy, also the sum of the elements' Pi in element order
  // (energy()'s first term, bit for bit), from the same element pass.
  // With keep_terms, each element's consistent tangent terms (the same
  // gradient and energy bits) go to the workspace's terms. Without, at the
  // nodal velocities of this problem's last element pass (bit for bit),
  // that pass's forces and energy are taken instead of a new pass.
  double nodal_forces(const std::vector<Vec2>& v, std::vector<Vec2>& F, double* element_energy = nullptr,
                      bool keep_terms = false) const;
  void residual(const Vec& u, Vec& R, double& scale) const;
  // residual() and energy() from one element pass (a line search's trial):
  // returns Pi(u), the same bits as energy(u).
  double residual_energy(const Vec& u, Vec& R, double& scale) const;
  // While on, residual() and residual_energy() also compute the elements'
  // consistent tangent terms at their u (the gradient and energy are the
  // same bits either way) and keep them, and a tangent(u, true) at that
  // very u scatters those instead of a second element pass: Newton's
  // full-step trial, which is usually the next iterate. Terms already kept
  // at that u are not formed again; they serve one tangent, and go with
  // constraints that change the DofMap or the pattern, or a new limiting
  // rate.
  void keep_tangent_terms(bool on) { keep_terms_ = on; }
  // Assembles the tangent (consistent or secant) at u into the workspace.
  const SpMat& tangent(const Vec& u, bool consistent);
  // The tangent's sparsity pattern (set_constraints' constraints and
  // couplings); its values are whatever the last assembly left.
  const SpMat& tangent_pattern() const { return ws_.assembler.matrix(); }
  bool solve(const Vec& u, bool consistent, const Vec& R, Vec& du);
  NewtonSystem newton_system();
  const StepView& view() const { return view_; }
  // Element e's data at nodal velocities v (for post-processing).
  RigidPlasticInput element_input(Index e, const std::vector<Vec2>& v) const;
  // Cold start: from u, one linear-viscous solve with the viscosity of the
  // given rate everywhere (RigidPlasticInput::viscous_floor), the start of
  // the Newton iteration when no previous velocity field exists.
  void viscous_predictor(double rate, Vec& u);
  double limiting_strain_rate() const { return epsdot_lim_; }
  void set_limiting_strain_rate(double rate) { epsdot_lim_ = rate, forget_passes(); }
  // N: the least force scale. A step in which nothing is loaded (bodies
  // approaching before their contact closes, a body at rest under a moving
  // virtual rigid one) has element forces at round-off only, and a
  // residual relative to them stays near 1 at the exact solution.
  void set_force_floor(double f) { force_floor_ = f; }

 private:
  // Pi given the elements' sum at nodal velocities v: less the external
  // power, plus the contact's terms (energy()'s and residual_energy()'s
  // end); the time from t0 counts as the residual's, then the contact's.
  double energy_from_elements(const std::vector<Vec2>& v, double elements, Clock::time_point t0) const;
  // nodal_forces() of residual() and residual_energy() at u, keeping the
  // tangent terms where keep_terms_ is on.
  double forces_at(const Vec& u, std::vector<Vec2>& v, std::vector<Vec2>& F, double* element_energy) const;
  // The elements' forces and energies at nodal velocities v into the
  // workspace (element_forces, element_values; their sum pass_energy_),
  // and with keep_terms the consistent tangent's terms, in the matrix or
  // per element (force_nodes: the contact reads elements' rows).
  void element_pass(const std::vector<Vec2>& v, bool keep_terms, bool force_nodes) const;
  // Whether the kept terms are at u (bit for bit) and nothing has written
  // over them since.
  bool kept_at(const Vec& u) const;
  // The element results at hand (kept terms, the last pass's forces) no
  // longer hold: what the elements see besides v changed (the limiting
  // rate, the predictor's viscous floor).
  void forget_passes() const { terms_kept_ = false, pass_id_ = 0; }

  const StepView& view_;
  const std::vector<std::array<double, 4>>& strain_;
  std::vector<std::array<double, 4>> yield_;  // MPa, law.yield(strain) per element and point
  const std::vector<ElementMaterial>& materials_;
  double epsdot_lim_;
  const std::vector<Vec2>& fext_;
  ContactFormulation& contact_;
  SolverWorkspace& ws_;
  double viscous_floor_ = 0;
  double force_floor_ = 0;
  bool keep_terms_ = false;
  // ws_.terms hold the consistent tangent's element terms at terms_u_ (this
  // problem's elements, limiting rate and constraints); where
  // terms_in_matrix_, the assembler holds their scatter instead.
  mutable bool terms_kept_ = false;
  mutable bool terms_in_matrix_ = false;
  mutable Vec terms_u_;
  mutable std::uint64_t terms_writes_ = 0;  // ws_.terms_writes when they were kept
  // The last element pass for forces: its nodal velocities, the elements'
  // energy sum, and ws_.force_passes after it (ws_.element_forces hold its
  // forces while that count stands; 0: none). A pass at the same
  // velocities (bit for bit) takes its results: the same inputs give the
  // same bits.
  mutable std::vector<Vec2> pass_v_;
  mutable double pass_energy_ = 0;
  mutable int pass_id_ = 0;
};

// Consistent nodal external forces of the tractions on the current
// configuration: F_a = int N_a t dS (dS = 2 pi r ds in axisymmetry).
struct TractionLoad;
std::vector<Vec2> traction_forces(const Mesh& mesh, const std::vector<Vec2>& x, Geometry g,
                                  const std::vector<TractionLoad>& loads);

}  // namespace rpfem
