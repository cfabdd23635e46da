// "direct": rigid dies as kinematic constraints, ALPID style (Oh, Lahoti,
// Altan 1981; Kobayashi, Oh, Altan 1989, sec. 8.4). A boundary node in
// contact with a die gets its normal velocity equal to the die's, imposed
// exactly by elimination in a nodal frame rotated to the die normal at the
// node's closest point, and slides freely along the die tangent.
//   Touch: a free candidate node that would reach a die within the step
//   shortens the step so that the first such node lands on it (limit_dt).
//   Release: a contact node whose normal nodal force turns tensile leaves.
//   Corners and arcs: the frame is taken from the die's closest point at
//   each step, so a node follows the die's actual surface.
// Friction on die contact is not in this formulation yet (see the notes).
#pragma once
#include <vector>

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
  StepCheck check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  std::optional<double> limit_dt(const StepView& v, const std::vector<Vec2>& vel) const override;
  std::optional<double> reference_speed(const std::string& name) const override;
  void contact_forces(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                      std::vector<Vec2>& out) const override;
  std::vector<std::string> load_names() const override;
  std::vector<Vec2> loads(const StepView& v, const std::vector<Vec2>& F) const override;
  std::vector<std::string> report_names() const override;
  std::vector<double> report() const override;

 private:
  struct Candidate {
    Index node;
    int die;          // the die this node may touch
    bool in_contact = false;
    DieProjection proj;  // at the start of the step
  };
  const Scene& scene_;
  std::vector<Candidate> cand_;
  double touch_tol_ = 0;    // mm
  double release_tol_ = 0;  // N, relative part of the force scale
  double sym_tol_ = 0;
  double max_penetration_ = 0;
  std::vector<std::string> touches_;  // found by begin_step, reported by check
  int contacts_ = 0;
};

}  // namespace rpfem
