// The enforcement axis of contact: how the rows of a discretization are
// satisfied (direct elimination, penalty, augmented Lagrangian, Ipopt's
// constrained minimization). An enforcement sees rows (contact_row.hpp),
// never the search or the surfaces; the hooks are the kernel's
// (model/contact_formulation.hpp) with the rows handed over.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "contact/contact_row.hpp"
#include "contact/discretization.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

class ContactEnforcement {
 public:
  virtual ~ContactEnforcement() = default;
  virtual std::string name() const = 0;
  // A configuration's rows (valid until the next call); the contact state
  // is carried over by the rows' identity (iface, key).
  virtual void begin_step(const StepView&, const std::vector<ContactRow>& rows) = 0;
  virtual void constraints(const StepView&, std::vector<NodeConstraint>&) const {}
  virtual void add_terms(const StepView&, const std::vector<Vec2>& v, TermSink&) const = 0;
  virtual TangentKind tangent() const { return {}; }
  // The nodes whose elements' force its terms read (TermSink::element_force).
  virtual void force_nodes(std::vector<Index>&) const {}
  // After a failed solve: whether it switched to a more robust scheme for
  // this solve (ContactFormulation::fall_back).
  virtual bool fall_back() { return false; }
  virtual void anchor_merit(const StepView&, const std::vector<Vec2>& v) {}
  virtual StepSolver* solver() { return nullptr; }
  // After a converged solve: the rows' results (results()), and whether the
  // contact state changed so that the step is solved again.
  virtual StepCheck settle(const StepView&, const std::vector<Vec2>& v, const std::vector<Vec2>& F) = 0;
  virtual const std::vector<RowResult>& results() const = 0;
  // Whether it places its contact nodes on the dies itself after each step
  // (place_on_surfaces); else ContactModel corrects the drift of nodes
  // pressing on curved dies.
  virtual bool places_on_surfaces() const { return false; }
  virtual double place_on_surfaces(const StepView&, std::vector<Vec2>& x) { return 0; }
  virtual void end_step(const StepView&, const std::vector<Vec2>& v) {}
  // Every member a solve changes, for ContactFormulation::save_state
  // (contact/saved_members.hpp).
  virtual std::any save_state() const = 0;
  virtual void restore_state(const std::any&) = 0;
  // Before a step's attempts: a new step begins. After an attempt (its
  // rows at the end configuration): whether it changed its own parameters
  // so that the step is solved again from its start
  // (ContactFormulation::retune; the stepper puts the state saved by
  // save_state back first); what changed, for the log.
  virtual void remember_start() {}
  virtual std::optional<std::string> retune() { return std::nullopt; }
  // The depth, over the local element size, it keeps the rows within when
  // it adapts to a tolerance (the adaptive penalty), 0 if it does not: a
  // row that ends an attempt deeper, where retune() did not cure it, has
  // the step redone shorter as under contact.landing_overshoot (that key,
  // when set, takes precedence).
  virtual double kept_depth() const { return 0; }
  // The factor it has put on row i's own stiffness (the adaptive penalty's
  // raises; 1 if none), carried to the new mesh's rows at a remesh
  // (ContactZones::Traction::row_factor, ContactRow::Prior).
  virtual double row_factor(std::size_t i) const { return 1.0; }
  // Its own per-step scalars: names and values in a fixed order.
  virtual void columns(std::vector<NamedValue>& out) const {}
  // Largest penetration per element size it measures itself (the end-of-
  // step gap of a constrained minimization), nullopt to use the rows' gaps.
  virtual std::optional<double> penetration_rel() const { return std::nullopt; }
  virtual void derived(std::vector<NamedValue>& out) const {}
  // With exact friction (its results then carry each row's stick or slip
  // state, RowResult::stick): the last solve's largest violation of the
  // law (ContactRecord::friction_violation); nullopt without.
  virtual std::optional<double> friction_violation() const { return std::nullopt; }
  // The row behind that violation and why, in words for the run's warning
  // (empty: none named).
  virtual std::string friction_violation_cause() const { return {}; }
};

}  // namespace rpfem
