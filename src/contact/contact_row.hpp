// The rows of contact: what a discretization hands an enforcement. A row is
// one constraint of non-penetration with its friction: the gap rate
// gamma_N and the slip rate gamma_T of a slave point against its master as
// weights on nodal velocities (contact/pair_kinematics.hpp, paper eq. 5, 9,
// 12), the gap, and the share of the contact surface it stands for. An
// enforcement sees rows only, never the search or the surfaces; a
// discretization knows nothing of how its rows are satisfied.
#pragma once
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "material/friction_law.hpp"
#include "contact/pair_kinematics.hpp"
#include "core/types.hpp"

namespace rpfem {

// One contact interface (a [[contact_pairs]] entry) as the discretization
// set it up.
struct ContactInterface {
  std::string name;        // "<body>-<die>" or "<body>-<with>"
  int die = -1;            // the master die, -1 between bodies
  std::array<int, 2> bodies{-1, -1};  // the body, and the other body (-1 for a die)
  FrictionLaw friction;
  double h = 0;            // mm, mean edge length of the (finer) slave surface at the start
  double sigma_ref = 0;    // MPa, the softer body's initial flow stress
  double area = 0;         // mm^2, the (finer) slave surface's area at the start
};

struct ContactRow {
  PairKinematics kin;
  int iface = 0;
  // Identity across configurations: (iface, key), key the slave node. An
  // enforcement carries its contact state (in contact, multipliers) by it.
  Index key = 0;
  double weight = 0;       // mm^2, the slave node's lumped contact area (all its surface edges)
  double h = 0;            // mm, the local element size at the slave node
  int master_element = -1; // the master segment's element (body master)
  double friction_share = 1;  // the share of the interface's friction this row carries (two pass: 1/2)
  // The direction the gap kin.gap0 is measured along: the master segment's
  // own normal (kin.n is the least-squares line's, paper Fig. 3, which
  // tilts by about gap / segment length away from contact), or the die's.
  // Landing control predicts the landing along it.
  Vec2 gap_normal = Vec2::Zero();
  // An instantaneous solve (StepView::moves false) and the slave clear of
  // its master: the row takes no part in the solve (it stays for landing
  // control and the gap field). Set by ContactModel.
  bool free = false;
  // mm: where its surfaces are closest over the row's support, if that is
  // not kin.gap0 (a mortar row's gap is a weighted average: a cone touching
  // a flat at one point leaves it open). NaN: kin.gap0.
  double touch_gap = std::numeric_limits<double>::quiet_NaN();
  double nearest() const { return std::isnan(touch_gap) ? kin.gap0 : touch_gap; }
  // Whether the row engages at once (a node landing on a surface: the load
  // jumps there, and landing control ends a step at it) or gradually (a
  // mortar row: its weighted gap closes as the contact zone grows over its
  // support, and the load with it).
  bool lands = true;
  // mm: the gap the row had when it was taken over at a remesh (contact
  // between bodies re-established on the new mesh, ContactModel): kin.gap0,
  // kin.gap_from and touch_gap are measured from it, so the row holds the
  // interface as it stood. Its true gap is kin.gap0 + gap_offset.
  double gap_offset = 0;
  double true_gap() const { return kin.gap0 + gap_offset; }
  // A solve's first rows after a remesh: the forces the old mesh's row
  // nearest to this one carried (ContactZones::tractions times this row's
  // weight), for an enforcement whose unknowns they are (a warm start,
  // the multipliers' counterpart of the velocities carried over). Unset
  // otherwise.
  struct Prior {
    double normal = 0, friction = 0;  // N, friction along this row's t
    bool stick = false;
    double row_factor = 1;  // the old row's factor on its stiffness (ContactEnforcement::row_factor)
  };
  std::optional<Prior> prior;
};

// Contact area and sticking bound of a row, given which rows are in
// contact: over the slave's surface edges with both ends in contact.
struct RowArea {
  double area = 0;  // mm^2
  double kw = 0;    // N, sum over those edges of k w (k = sigma_bar / sqrt 3, the shear yield
                    // stress of the softer side; times friction_share)
};

// An enforcement's verdict on each row after a converged solve.
struct RowResult {
  bool in_contact = false;
  double normal = 0;    // N, normal force (> 0 pressing)
  double friction = 0;  // N, friction force on the slave along t = (-n_y, n_x)
  double slip = 0;      // mm/s, gamma_T
  // Exact friction (ContactEnforcement::friction_violation): 1 sticking, -1
  // slipping; 0 not in contact, frictionless, or the arctan law.
  int stick = 0;
  // The force on the slave node when it is not c_0 (N n + T t): a node held
  // by elimination whose reaction also holds the kernel's constraints there
  // (a die's apex on the axis: the whole nodal reaction is the die's load,
  // its radial part cancelling around the circumference).
  std::optional<Vec2> slave_force;
};

}  // namespace rpfem
