#include "auglag/auglag_enforcement.hpp"

#include "contact/friction_treatment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rpfem {

namespace {

RegularizedSettings read_settings(const Scene& scene, CaseSection& s, const ContactDiscretization& disc) {
  RegularizedSettings r;
  const double size = scene.mesh.size();
  const double factor = s.real("beta_factor", 1e-2, Range::positive(), "times the penalty's default beta");
  const auto beta = s.optional_real("beta", Range::positive(), "MPa s/mm (replaces the default)");
  r.beta_hat = default_beta_hat(scene, disc, factor, beta);
  r.gap_correction = true;  // the multiplier acts on the end-of-step gap
  r.touch_tol = s.real("touch_tolerance", 1e-7, Range::positive(), "relative to the bodies' size") * size;
  r.release_tol = 0;
  r.speed_scale = scene.largest_speed();
  return r;
}

// Aitken's relaxation factor kept within these (a factor below 1 slows
// the plain update; one far above it follows round-off).
constexpr double kOmegaMin = 1.0, kOmegaMax = 1e3;

}  // namespace

AugLagEnforcement::AugLagEnforcement(const Scene& scene, CaseSection settings, const ContactDiscretization& disc)
    : RegularizedEnforcement(disc, read_settings(scene, settings, disc)) {
  require_friction_treatment(scene, name(), {});
  tol_primal_ = settings.real("tolerance", 1e-9, Range::positive(),
                              "largest end-of-step penetration, relative to the element size");
  tol_compl_ = settings.real("complementarity_tolerance", 1e-8, Range::positive(),
                             "largest |N g_end / dt| relative to the total normal force times the speed scale");
  max_augmentations_ = settings.integer("max_augmentations", 20, 1, 1000);
  aitken_ = settings.flag("aitken", true);
  speed_scale_ = scene.largest_speed();
}

void AugLagEnforcement::begin_step(const StepView& v, const std::vector<ContactRow>& rows) {
  RegularizedEnforcement::begin_step(v, rows);
  // Each row's multiplier starts from its last normal force.
  auto& lambda = rows_.lambda();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto it = lambda_.find({rows[i].iface, rows[i].key});
    lambda[i] = it != lambda_.end() ? it->second : 0.0;
  }
  primal_ = complementarity_ = 0;
  depth_ = 0;
  for (const ContactRow& r : rows) depth_ = std::max(depth_, -r.kin.gap0 / r.h);
  solve_augmentations_ = 0;
  last_step_.clear();
  omega_ = 1;
  if (v.step != step_) augmentations_ = 0, step_ = v.step;
}



void AugLagEnforcement::measure(const StepView& v, const std::vector<Vec2>& vel) {
  const auto& rows = rows_.rows();
  const auto& res = rows_.results();
  double total = 0;
  for (const RowResult& r : res) total += std::max(r.normal, 0.0);
  primal_ = complementarity_ = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!rows_.engaged(i)) continue;
    const double r = rows_.end_gap_rate(i, vel);  // g_end / dt, mm/s
    primal_ = std::max(primal_, std::max(0.0, -r * v.dt) / rows[i].h);
    if (total > 0) complementarity_ = std::max(complementarity_, std::abs(res[i].normal * r) / (total * speed_scale_));
  }
}

StepCheck AugLagEnforcement::settle(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) {
  StepCheck out = settle_state(v, vel);
  measure(v, vel);
  const auto& rows = rows_.rows();
  const auto& res = rows_.results();
  // The multipliers carried to the next configuration: this solve's forces.
  for (std::size_t i = 0; i < rows.size(); ++i)
    lambda_[{rows[i].iface, rows[i].key}] = rows_.engaged(i) ? res[i].normal : 0.0;
  if (out.resolve) return out;  // the contact state or the smoothing changed: solve again first
  const bool met = primal_ <= tol_primal_ && complementarity_ <= tol_compl_;
  if (met) return out;
  if (solve_augmentations_ >= max_augmentations_) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "augmented Lagrangian: %d augmentations left penetration %.1e, complementarity %.1e",
                  solve_augmentations_, primal_, complementarity_);
    out.events.push_back(buf);
    return out;
  }
  update_multipliers();
  ++augmentations_, ++solve_augmentations_;
  out.resolve = out.warm = true;
  return out;
}

void AugLagEnforcement::update_multipliers() {
  // Uzawa's update is the fixed point lambda = G(lambda) = N(lambda) =
  // max(0, lambda - beta r(lambda)); it contracts by about K / (K + beta)
  // per update, K the stiffness the rows see (the bodies' volumetric
  // penalty makes it large). Aitken's relaxation of the fixed point (Irons
  // and Tuck 1969; Kuettler and Wall 2008, eq. 44):
  //   lambda <- max(0, lambda + omega d),  d = G(lambda) - lambda,
  //   omega <- -omega d_prev . (d - d_prev) / |d - d_prev|^2
  // (omega = 1 the first time, and whenever the rows changed).
  const auto& rows = rows_.rows();
  const auto& res = rows_.results();
  auto& lambda = rows_.lambda();
  std::vector<double> d(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) d[i] = (rows_.engaged(i) ? res[i].normal : 0.0) - lambda[i];
  if (aitken_ && last_step_.size() == d.size()) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double dd = d[i] - last_step_[i];
      num += last_step_[i] * dd, den += dd * dd;
    }
    if (den > 0) omega_ = std::clamp(-omega_ * num / den, kOmegaMin, kOmegaMax);
  }
  for (std::size_t i = 0; i < rows.size(); ++i) lambda[i] = std::max(0.0, lambda[i] + omega_ * d[i]);
  last_step_ = std::move(d);
}

void AugLagEnforcement::columns(std::vector<NamedValue>& out) const {
  out.push_back({"augmentations", double(augmentations_)});
  out.push_back({"kkt_primal", primal_});
  out.push_back({"kkt_complementarity", complementarity_});
}

void AugLagEnforcement::derived(std::vector<NamedValue>& out) const {
  derived_betas("auglag", out);
  out.insert(out.end(), {{"auglag.tolerance", tol_primal_},
                         {"auglag.complementarity_tolerance", tol_compl_},
                         {"auglag.max_augmentations", double(max_augmentations_)},
                         {"auglag.aitken", aitken_ ? 1.0 : 0.0}});
}

}  // namespace rpfem
