// "direct": rigid dies as kinematic constraints, ALPID style (Oh, Lahoti,
// Altan 1981; Kobayashi, Oh, Altan 1989, sec. 8.4). A boundary node in
// contact with a die gets its normal velocity equal to the die's, imposed
// exactly by elimination in a nodal frame rotated to the die normal at the
// node's closest point, and slides along the die tangent against friction.
//   Touch: a free candidate node that would reach a die within the step
//   shortens the step so that the first such node lands on it (limit_dt).
//   Release: a contact node whose normal nodal force turns tensile leaves.
//   Corners and arcs: the frame is taken from the die's closest point at
//   each step, and after each step the contact nodes are placed back on the
//   die surface (a node sliding along an arc otherwise drifts off it by
//   (v dt)^2 / 2R per step).
//   Friction (contact_friction.hpp): the arctan law's dissipation potential
//   at each contact node, with its exact gradient and Hessian.
#pragma once
#include <vector>

#include "direct/contact_friction.hpp"
#include "io/case_file.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

class DirectContact final : public ContactFormulation {
 public:
  DirectContact(const Scene& scene, CaseSection settings);
  std::string name() const override { return "direct"; }

  void begin_step(const StepView& v) override;
  void constraints(const StepView& v, std::vector<NodeConstraint>& out) const override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override;
  StepCheck check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  std::optional<double> limit_dt(const StepView& v, const std::vector<Vec2>& vel) const override;
  std::optional<double> reference_speed(const std::string& name) const override;
  void contact_forces(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                      std::vector<Vec2>& out) const override;
  std::vector<std::string> load_names() const override;
  std::vector<Vec2> loads(const StepView& v, const std::vector<Vec2>& F) const override;
  void node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const override;
  std::vector<std::string> report_names() const override;
  std::vector<double> report() const override;
  double place_on_surfaces(const StepView& v, std::vector<Vec2>& x) override;

 private:
  double neutral_point(int die) const;  // x (mm) where the slip changes sign

  const Scene& scene_;
  std::vector<ContactNode> cand_;
  std::vector<ContactEdge> edges_;
  ContactFriction friction_;
  double touch_tol_ = 0;    // mm
  double release_tol_ = 0;  // relative to the largest contact force
  double coulomb_tol_ = 0;  // relative change of the Coulomb bounds between passes
  double coulomb_relax_ = 1;  // relaxation of the Coulomb fixed point in this step
  double sym_tol_ = 0;
  double max_penetration_ = 0, max_placement_ = 0, max_overshoot_ = 0, coulomb_change_ = 0;
  std::vector<int> neutral_dies_;  // dies with friction: their neutral point is reported
  std::vector<std::string> touches_;  // found by begin_step, reported by check
  int contacts_ = 0, coulomb_updates_ = 0;
};

}  // namespace rpfem
