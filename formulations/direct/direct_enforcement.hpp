// "direct": rigid dies as kinematic constraints, ALPID style (Oh, Lahoti,
// Altan 1981; Kobayashi, Oh, Altan 1989, sec. 8.4). A slave node in
// contact with a die gets its normal velocity equal to the die's, imposed
// exactly by elimination in a nodal frame rotated to the die normal at the
// node's closest point (the row's n), and slides along the die tangent
// against friction.
//   Touch: a free node on (or by round-off just inside) the die; landing
//   control (contact/contact_model.hpp) ends a step where the first free
//   node lands.
//   Release: a contact node whose normal nodal force turns tensile leaves.
//   Corners and arcs: after each step the contact nodes are placed back on
//   the die surface (a node sliding along an arc otherwise drifts off it by
//   (v dt)^2 / 2R per step).
//   Friction: the arctan law's potential B psi(gamma_T) per contact row
//   (contact/row_terms.hpp): the friction factor's B = m k w fixed in a
//   solve; Coulomb's B = min(mu N, k w) with N the row's normal reaction,
//   N = n . F_s, F_s the elements' force at the node (the reaction the
//   elimination holds), evaluated at every Newton iterate and linearized
//   in the tangent (d B / d v = mu n^T K_s, K_s the elements' Hessian rows
//   of the node: unsymmetric, UMFPACK), so the bound converges with the
//   velocities. A node on two dies, whose reaction is split between them,
//   keeps the bound of the last solve, by a fixed point over the step's
//   solves until B stops changing (relaxed when it oscillates).
// Rows against dies only: contact between bodies needs another enforcement.
#pragma once
#include <map>
#include <utility>
#include <vector>

#include "contact/enforcement.hpp"
#include "contact/row_terms.hpp"
#include "contact/saved_members.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

class DirectEnforcement final : public ContactEnforcement {
 public:
  DirectEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc);
  std::string name() const override { return "direct"; }
  void begin_step(const StepView& v, const std::vector<ContactRow>& rows) override;
  void constraints(const StepView& v, std::vector<NodeConstraint>& out) const override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override;
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  const std::vector<RowResult>& results() const override { return results_; }
  // Coulomb: its bound follows the reaction within Newton (unsymmetric).
  // Live Coulomb bounds: not a potential; the line search's merit is the
  // energy with each bound frozen at the iterate (anchor_merit).
  TangentKind tangent() const override {
    return coulomb_ && coulomb_in_newton_ && !fixed_point_ ? TangentKind{false, false, true} : TangentKind{};
  }
  // A solve whose Newton failed with live bounds is solved again with the
  // bounds fixed within it (the fixed point over its passes).
  bool fall_back() override;
  void anchor_merit(const StepView&, const std::vector<Vec2>&) override {
    if (coulomb_ && coulomb_in_newton_) merit_bound_ = tangent_bound_;
  }
  void force_nodes(std::vector<Index>& out) const override;
  bool places_on_surfaces() const override { return true; }
  double place_on_surfaces(const StepView& v, std::vector<Vec2>& x) override;
  void columns(std::vector<NamedValue>& out) const override;
  std::any save_state() const override {
    return save_members(rows_, state_, now_, kw_, bound_, live_, started_, tangent_bound_, merit_bound_, results_,
                        touches_, smoothing_, fixed_point_, coulomb_change_, max_placement_, max_overshoot_);
  }
  void restore_state(const std::any& saved) override {
    restore_members(saved, rows_, state_, now_, kw_, bound_, live_, started_, tangent_bound_, merit_bound_, results_,
                    touches_, smoothing_, fixed_point_, coulomb_change_, max_placement_, max_overshoot_);
  }

 private:
  struct State {
    bool in_contact = false;
    double normal = 0;  // N, the last converged solve's normal reaction (> 0 pressing)
  };
  // Moves every bound toward the law's value at the current normal forces
  // by the fraction relax; returns the largest change relative to the
  // largest bound (0 if nothing changed).
  double update_bounds(double relax);
  const FrictionLaw& law(std::size_t i) const;
  double smoothing_speed(std::size_t i) const;

  const Scene& scene_;
  const ContactDiscretization& disc_;
  const std::vector<ContactRow>* rows_ = nullptr;
  std::map<std::pair<int, Index>, State> state_;  // by row identity
  std::vector<State> now_;       // per row
  std::vector<double> kw_, bound_;
  // Per row: a Coulomb row in contact, alone on its node, whose bound
  // follows its reaction within Newton (set_live).
  std::vector<char> live_;
  void set_live();
  // The rows in contact, by slave node.
  std::map<Index, std::vector<std::size_t>> contact_rows_by_node() const;
  // Whether this solve assembled a tangent yet (add_terms: a live bound
  // from then on).
  mutable bool started_ = false;
  // The bounds of the last tangent's iterate (Newton anchors its merit at
  // the iterate whose tangent it just solved with), and the anchored ones
  // (-1: none).
  mutable std::vector<double> tangent_bound_;
  std::vector<double> merit_bound_;
  std::vector<RowResult> results_;
  std::vector<std::string> touches_;
  SmoothingContinuation smoothing_;
  bool coulomb_ = false;
  bool coulomb_in_newton_ = true;  // coulomb_update: "newton" (live bounds) or "passes" (the fixed point only)
  bool fixed_point_ = false;       // this solve fell back to the fixed point
  double speed_scale_ = 0;
  double touch_tol_ = 0, release_tol_ = 0, coulomb_tol_ = 0;
  double coulomb_relax_ = 1, coulomb_change_ = 0;
  double max_placement_ = 0, max_overshoot_ = 0;
};

}  // namespace rpfem
