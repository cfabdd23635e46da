#include "direct/contact_friction.hpp"

#include <algorithm>
#include <cmath>

#include "fem/edge_weights.hpp"

namespace rpfem {

namespace {
Vec2 tangent_of(const Vec2& n) { return Vec2(-n(1), n(0)); }
}  // namespace

ContactFriction::ContactFriction(const std::vector<Die>& dies, double speed_scale)
    : dies_(dies) {
  for (const Die& d : dies) {
    a_.push_back(d.friction.a_relative * speed_scale);
    any_ = any_ || d.friction.kind != FrictionLaw::Kind::None;
    coulomb_ = coulomb_ || d.friction.kind == FrictionLaw::Kind::Coulomb;
    if (d.friction.kind != FrictionLaw::Kind::None)
      a_factor_ = std::max(a_factor_, 0.1 / d.friction.a_relative);
  }
}

bool ContactFriction::relax_smoothing() {
  if (a_factor_ <= 1) return false;
  a_factor_ = std::max(1.0, a_factor_ / 10);
  return true;
}

void ContactFriction::update_weights(const StepView& v, const std::vector<ContactEdge>& edges,
                                     std::vector<ContactNode>& nodes) const {
  for (auto& c : nodes) c.weight = c.k_weight = 0;
  for (const auto& e : edges) {
    ContactNode &a = nodes[e.a], &b = nodes[e.b];
    if (!a.in_contact || !b.in_contact || a.die != b.die) continue;
    const auto w = edge_weights((*v.x)[a.node], (*v.x)[b.node], v.geometry);
    const double k = (*v.flow_stress)[e.element] / std::sqrt(3.0);  // shear yield stress (von Mises)
    a.weight += w[0];
    b.weight += w[1];
    a.k_weight += k * w[0];
    b.k_weight += k * w[1];
  }
}

double ContactFriction::update_bounds(std::vector<ContactNode>& nodes, double relax) const {
  double change = 0, largest = 0;
  for (auto& c : nodes) {
    const FrictionLaw& law = dies_[c.die].friction;
    double B = 0;
    if (c.in_contact) {
      if (law.kind == FrictionLaw::Kind::Factor) B = law.m * c.k_weight;  // tau = m k
      else if (law.kind == FrictionLaw::Kind::Coulomb)
        B = std::min(law.mu * std::max(c.normal_force, 0.0), c.k_weight);  // tau = min(mu p, k)
    }
    change = std::max(change, std::abs(B - c.bound));
    largest = std::max(largest, B);
    c.bound += relax * (B - c.bound);
  }
  return largest > 0 ? change / largest : 0.0;
}

void ContactFriction::add_terms(const StepView& v, const std::vector<Vec2>& vel,
                                const std::vector<ContactNode>& nodes, TermSink& sink) const {
  for (const auto& c : nodes) {
    if (!c.in_contact || c.bound <= 0) continue;
    const Vec2 t = tangent_of(c.proj.normal);
    const double s = (vel[c.node] - dies_[c.die].motion.velocity(v.time)).dot(t);
    const ArctanPotential p = arctan_potential(s, smoothing_speed(c.die));
    const Vec2 g = c.bound * p.dpsi * t;
    const Eigen::Matrix2d H = c.bound * p.d2psi * t * t.transpose();
    sink.add(&c.node, 1, c.bound * p.psi, g.data(), H.data());
  }
}

void ContactFriction::record(const StepView& v, const std::vector<Vec2>& vel, std::vector<ContactNode>& nodes) const {
  for (auto& c : nodes) {
    c.friction = Vec2::Zero();
    c.slip = 0;
    if (!c.in_contact) continue;
    const Vec2 t = tangent_of(c.proj.normal);
    c.slip = (vel[c.node] - dies_[c.die].motion.velocity(v.time)).dot(t);
    if (c.bound > 0) c.friction = -c.bound * arctan_potential(c.slip, smoothing_speed(c.die)).dpsi * t;
  }
}

}  // namespace rpfem
