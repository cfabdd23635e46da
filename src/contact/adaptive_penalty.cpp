#include "contact/adaptive_penalty.hpp"

#include <algorithm>

namespace rpfem {

namespace {

// The depth a raise aims at, over the tolerance: (1) holds at a fixed
// force, and the force changes with the re-solve (the row presses more
// where its neighbours press less), so the aim is below the tolerance.
constexpr double kAim = 0.5;
// A re-solve that leaves more than this share of the last attempt's
// largest depth is not the penalty's compliance: no further raise.
constexpr double kProgress = 0.5;
// At most this many re-solves per step (each raise at least doubles a
// factor, so f_max bounds them too).
constexpr int kMaxRaises = 8;

}  // namespace

double AdaptivePenalty::largest_factor() const {
  double f = 1;
  for (const auto& [key, value] : factor_) f = std::max(f, value);
  return f;
}

PenaltyRaise AdaptivePenalty::raise(const std::vector<ContactRow>& rows) {
  PenaltyRaise out;
  for (const ContactRow& r : rows)
    if (!r.free && r.kin.gap0 < 0) out.depth = std::max(out.depth, -r.kin.gap0 / r.h);
  out.largest_factor = largest_factor();
  if (!s_.on || !(out.depth > s_.tolerance) || raises_ >= kMaxRaises) return out;
  if (raises_ > 0 && !(out.depth <= kProgress * last_depth_)) {
    for (const auto& [key, f] : replaced_) factor_[key] = f;
    replaced_.clear();
    out.largest_factor = largest_factor();
    return out;
  }
  replaced_.clear();
  for (const ContactRow& r : rows) {
    if (r.free || !(-r.kin.gap0 > s_.tolerance * r.h)) continue;
    const double old = factor(r);
    const double next = std::min(s_.max_factor, old * (-r.kin.gap0 / r.h) / (kAim * s_.tolerance));
    if (!(next > old)) continue;  // at the cap
    replaced_[{r.iface, r.key}] = old;
    factor_[{r.iface, r.key}] = next;
    ++out.rows;
  }
  if (out.rows > 0) {
    ++raises_;
    last_depth_ = out.depth;
    out.largest_factor = largest_factor();
  }
  return out;
}

}  // namespace rpfem
