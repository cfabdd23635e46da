// "penalty": the reference paper's method (Jang and Hwang 2002, eq. 3-12):
// each row carries the penalty (beta / 2) min(r, 0)^2 on its predicted
// end-of-step gap rate r (contact/row_terms.hpp, with lambda = 0), and the
// friction of its law with the consistent tangent; the contact state as in
// contact/regularized_rows.hpp.
//   beta = beta_hat w_s per row, w_s the slave node's lumped contact area;
//   default beta_hat = 1e4 sigma_ref L / (v_ref h): ten thousand times the
//   stiffness of an element of size h at the reference strain rate
//   v_ref / L (sigma_ref the softer body's initial flow stress), so the
//   end-of-step penetration is about p dt / beta_hat = (stroke increment /
//   L) h / 1e4 (p = sigma_ref). An instantaneous solve (no gap yet) lets
//   the bodies approach at p / beta_hat, 1e-4 of v_ref h / L: the two-pass
//   patch test's first solve is uniform to 4e-4 with it, 3.5e-3 with 1e3
//   (docs/decisions.md); Newton's cost barely changes (Test II: +5 %).
// adapt (on unless the case gives beta_factor or beta): a step that ends
// with a row deeper than run.penetration_tolerance is solved again with
// that row's beta raised, up to beta_max_factor times
// (contact/adaptive_penalty.hpp, docs/theory.md).
#pragma once
#include <string>
#include <vector>

#include "contact/regularized_rows.hpp"
#include "io/case_file.hpp"
#include "model/scene.hpp"

namespace rpfem {

class PenaltyEnforcement final : public RegularizedEnforcement {
 public:
  PenaltyEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc);
  std::string name() const override { return "penalty"; }
  StepCheck settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) override {
    return settle_state(v, vel);
  }
  void derived(std::vector<NamedValue>& out) const override { derived_betas("penalty", out); }
  void columns(std::vector<NamedValue>& out) const override { adaptive_columns(out); }
};

}  // namespace rpfem
