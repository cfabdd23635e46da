// A contact treatment as the product of its two axes: a discretization
// (which rows exist) and an enforcement (how they are satisfied). What does
// not depend on either is done here, once, for every combination: the
// sparsity of the rows, landing control (a free slave predicted to land
// within the step shortens it to the landing), and the record of a solve
// (contact forces from the rows' results, die loads, contact areas and
// pressures, penetration, the fields of result.h5).
#pragma once
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "contact/discretization.hpp"
#include "contact/enforcement.hpp"
#include "geometry/die.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

struct Scene;

struct ContactModelSettings {
  bool landing_control = true;  // contact.landing_control
  // contact.landing_overshoot: the depth, over the local element size, a
  // row may end a step at beyond where it started and beyond contact;
  // deeper, the step is redone shorter (ContactModel::overshoot). 0: off.
  double landing_overshoot = 0;
};

class ContactModel final : public ContactFormulation {
 public:
  ContactModel(const Scene& scene, std::unique_ptr<ContactDiscretization> disc,
               std::unique_ptr<ContactEnforcement> enf, ContactModelSettings settings);

  ContactInfo info() const override;
  void begin_step(const StepView& v) override;
  void constraints(const StepView& v, std::vector<NodeConstraint>& out) const override { enf_->constraints(v, out); }
  void couplings(const StepView& v, std::vector<std::vector<Index>>& out) const override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override {
    enf_->add_terms(v, vel, sink);
  }
  TangentKind tangent() const override { return enf_->tangent(); }
  void force_nodes(const StepView&, std::vector<Index>& out) const override { enf_->force_nodes(out); }
  bool fall_back() override { return enf_->fall_back(); }
  void anchor_merit(const StepView& v, const std::vector<Vec2>& vel) override { enf_->anchor_merit(v, vel); }
  StepSolver* solver() override { return enf_->solver(); }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  std::optional<double> limit_dt(const StepView& v, const std::vector<Vec2>& vel) const override;
  bool controls_landings() const override { return settings_.landing_control; }
  void remember_start_gaps() override;
  std::optional<double> overshoot() const override;
  std::optional<std::string> retune() override { return enf_->retune(); }
  double place_on_surfaces(const StepView& v, std::vector<Vec2>& x) override;
  void end_step(const StepView& v, const std::vector<Vec2>& vel) override;
  std::any save_state() const override;
  void restore_state(const std::any& saved) override;
  ContactZones contact_zones(const std::vector<Vec2>& x) const override;
  void take_over(const ContactZones& zones) override {
    taken_ = zones;
    disc_->take_over(zones);
  }
  ContactRecord record(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) const override;

  const std::vector<ContactRow>& rows() const { return rows_; }
  const ContactEnforcement& enforcement() const { return *enf_; }
  const ContactDiscretization& discretization() const { return *disc_; }

 private:
  // The generic columns (names and, after a solve, values), then the
  // discretization's and the enforcement's.
  void columns(const StepView* v, std::vector<NamedValue>& out) const;
  double neutral_point(const StepView& v, int die) const;
  // contact.landing_overshoot, or where it is off the depth the enforcement
  // keeps (ContactEnforcement::kept_depth).
  double overshoot_tolerance() const {
    return settings_.landing_overshoot > 0 ? settings_.landing_overshoot : enf_->kept_depth();
  }
  // Rows between bodies in the zones taken over: their gaps now become
  // their zero (offsets_), once, at the first step after a remesh.
  void take_over_rows(const StepView& v);

  const Scene& scene_;
  std::unique_ptr<ContactDiscretization> disc_;
  std::unique_ptr<ContactEnforcement> enf_;
  ContactModelSettings settings_;
  std::vector<ContactRow> rows_;
  std::vector<std::string> events_;
  // The nodes of the rows in contact at the last settled solve (slave and
  // master), per interface: the band an instantaneous solve counts their
  // rows touching in.
  std::set<std::pair<int, Index>> touching_;
  // Each row's gap at the step's start (mm), with contact.landing_overshoot.
  std::map<std::pair<int, Index>, double> start_gaps_;
  std::vector<int> friction_dies_;  // dies with friction: their neutral point is reported
  bool any_bodies_ = false;
  double sym_tol_ = 0;
  double max_drift_ = 0;       // mm, the last step's largest drift corrected (place_on_surfaces)
  std::vector<Vec2> solved_;   // the last settled solve's velocities
  ContactZones taken_;         // taken over from before a remesh, until the first step
  // mm, per row (iface, key) taken over at a remesh and in contact since,
  // or out of contact but still inside its master: its gap then, held as
  // its zero (ContactRow::gap_offset; end_step drops it).
  std::map<std::pair<int, Index>, double> offsets_;
};

}  // namespace rpfem
