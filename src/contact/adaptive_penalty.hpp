// A penalty that keeps a penetration tolerance (after Bussetta, Marceau and
// Ponthot 2012, Comput. Mech. 49, 259-275; FEBio's auto_penalty, MOOSE's
// adaptivity_penalty_normal = BUSSETTA). A row's term (beta / 2) min(r, 0)^2
// on its predicted end-of-step gap rate r (contact/row_terms.hpp) presses
// with N = -beta r, so the step ends with the row at the depth
//   d = -r dt = N dt / beta                                        (1)
// and at a given force the depth falls as 1 / beta. After a step whose end
// configuration has a row deeper than the tolerance tau (over the local
// element size h, run.penetration_tolerance), each such row's factor on
// its beta is multiplied by the ratio (1) asks for to end at tau / 2,
//   f <- min(f_max, f (d / h) / (tau / 2)),
// and the step is solved again from its start. The factors are kept by the
// rows' identity for the steps after (a row that needed a stiffer penalty
// at one step needs it at the next: the force grows with the stroke) and
// never lowered. Raising stops at f_max, and when a re-solve has not
// halved the largest depth: a depth that is not the penalty's compliance
// (a slave sliding over a master's node: core_in_sleeve's 3.2e-3 at beta
// 1, 10 and 100 times the default alike). That raise is taken back (it
// would only stiffen the tangent) and the depth left to landing control's
// redo of the step, shorter (ContactEnforcement::kept_depth).
#pragma once
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "contact/contact_row.hpp"

namespace rpfem {

struct PenaltyAdaptation {
  bool on = false;
  double tolerance = 0;   // largest end-of-step depth over the local element size (tau)
  double max_factor = 1;  // f_max: a row's beta at most this times its own
};

// What one raise did.
struct PenaltyRaise {
  int rows = 0;              // rows raised (0: the step stands)
  double depth = 0;          // the attempt's largest depth over the element size
  double largest_factor = 1; // the largest factor in force after it
};

class AdaptivePenalty {
 public:
  explicit AdaptivePenalty(PenaltyAdaptation s) : s_(s) {}
  const PenaltyAdaptation& settings() const { return s_; }
  // The factor on a row's beta (1 unless raised).
  double factor(const ContactRow& r) const {
    const auto it = factor_.find({r.iface, r.key});
    return it == factor_.end() ? 1.0 : it->second;
  }
  // A row's factor carried over a remesh (ContactRow::Prior::row_factor,
  // the old mesh's row nearest it): kept if larger than its own.
  void carry(const ContactRow& r, double f) {
    if (f > factor(r)) factor_[{r.iface, r.key}] = std::min(s_.max_factor, f);
  }
  // Before a step's attempts.
  void begin_step() { raises_ = 0, last_depth_ = INFINITY, replaced_.clear(); }
  // After an attempt, its rows at the end configuration (those not free):
  // the factors of the rows deeper than the tolerance raised (above).
  PenaltyRaise raise(const std::vector<ContactRow>& rows);
  // Re-solves asked for in this step, and the largest factor in force.
  int raises() const { return raises_; }
  double largest_factor() const;

 private:
  PenaltyAdaptation s_;
  std::map<std::pair<int, Index>, double> factor_;  // by row identity (iface, key)
  int raises_ = 0;
  double last_depth_ = INFINITY;  // the last raised attempt's largest depth
  // The factors the last raise replaced (1: none), to take it back.
  std::map<std::pair<int, Index>, double> replaced_;
};

}  // namespace rpfem
