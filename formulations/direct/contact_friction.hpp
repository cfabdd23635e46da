// Friction at the direct formulation's contact nodes (nodal integration of
// the friction stress over each node's share of the contact surface).
//
// Each contact node i carries a friction bound B_i = tau_max,i * w_i (N), w_i
// its lumped contact area (fem/edge_weights.hpp) over the boundary edges of
// which both ends touch the same die. The friction force on the node is the
// arctan law (contact/friction_law.hpp; paper eq. 11-12)
//     f_i = -B_i psi'(s_i) t_i,   s_i = (v_i - v_die) . t_i,
// the gradient of the potential B_i psi(s_i) added to the step's functional,
// with Hessian B_i psi''(s_i) t_i t_i^T (exact for fixed B_i).
//   friction factor: B_i = m sum_e k_e w_e,i   (k_e = sigma_bar_e / sqrt 3 of
//                    the edge's element, fixed in the step: sigma_bar at the
//                    step's strain; its rate part from the last solve)
//   Coulomb:         B_i = min(mu N_i, sum_e k_e w_e,i), N_i the node's
//                    normal force; fixed point over the step's contact
//                    passes until B stops changing (update_bounds).
#pragma once
#include <vector>

#include "contact/friction_law.hpp"
#include "geometry/die.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

struct ContactNode {
  Index node = 0;
  int die = 0;
  bool in_contact = false;
  DieProjection proj;         // at the start of the step
  double weight = 0;          // mm^2, contact area share
  double k_weight = 0;        // N, sum_e k_e w_e,i: the sticking (shear-yield) bound
  double normal_force = 0;    // N, of the last converged solve (> 0 pressing)
  double bound = 0;           // N, B_i
  Vec2 friction = Vec2::Zero();  // N, friction force on the body, last solve
  double slip = 0;            // mm/s, s_i of the last solve
};

struct ContactEdge {
  int a = 0, b = 0;   // indices into the contact node list
  Index element = 0;  // the element the edge belongs to
};

class ContactFriction {
 public:
  // a = a_relative * speed_scale (mm/s).
  ContactFriction(const std::vector<Die>& dies, double speed_scale);
  bool any() const { return any_; }
  double smoothing_speed(int die) const { return a_[die] * a_factor_; }
  // Contact areas and shear-yield bounds from the current contact state.
  void update_weights(const StepView& v, const std::vector<ContactEdge>& edges, std::vector<ContactNode>& nodes) const;
  // Moves B_i toward the law's value at the current normal forces by the
  // fraction relax (1: all the way; less damps an oscillating Coulomb fixed
  // point); returns the largest distance |B_law - B_old| relative to the
  // largest bound (0 if nothing changed).
  double update_bounds(std::vector<ContactNode>& nodes, double relax = 1.0) const;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, const std::vector<ContactNode>& nodes,
                 TermSink& sink) const;
  // Stores the friction forces and slips of the converged solve.
  void record(const StepView& v, const std::vector<Vec2>& vel, std::vector<ContactNode>& nodes) const;
  bool coulomb() const { return coulomb_; }
  // Continuation in the smoothing speed for the run's first solve (from
  // rest, the arctan law with a small a is nearly non-smooth and Newton
  // may not find the sliding directions): a starts at the larger of a and
  // 0.1 of the speed scale and is divided by 10 per solve until it reaches
  // its value. Returns true while a was still enlarged (solve again).
  bool relax_smoothing();

 private:
  const std::vector<Die>& dies_;
  std::vector<double> a_;
  double a_factor_ = 1;  // a_eff = a * a_factor_ (continuation)
  bool any_ = false, coulomb_ = false;
};

}  // namespace rpfem
