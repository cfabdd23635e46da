// The arctan friction law (paper eq. 11-12) and the direct formulation's
// nodal friction terms: the potential's derivatives against finite
// differences, the contact areas and the friction bounds of both laws.
#include <gtest/gtest.h>

#include <cmath>

#include "contact/friction_law.hpp"
#include "direct/contact_friction.hpp"

using namespace rpfem;

TEST(ArctanPotential, DerivativesMatchFiniteDifferences) {
  const double a = 1e-3;
  for (double s : {-3.0, -2e-3, -1e-4, 0.0, 5e-5, 1e-3, 0.7, 40.0}) {
    const double h = 1e-7 * std::max(std::abs(s), a);
    const ArctanPotential p = arctan_potential(s, a), pp = arctan_potential(s + h, a), pm = arctan_potential(s - h, a);
    EXPECT_NEAR(p.dpsi, (pp.psi - pm.psi) / (2 * h), 1e-6 * std::max(1.0, std::abs(p.dpsi))) << s;
    EXPECT_NEAR(p.d2psi, (pp.dpsi - pm.dpsi) / (2 * h), 1e-5 * p.d2psi) << s;
  }
  // Limits: the friction stress tends to tau_max as |s| >> a, and psi to |s|.
  EXPECT_NEAR(arctan_potential(1e3, 1e-3).dpsi, 1.0, 1e-6);
  EXPECT_NEAR(arctan_potential(-1e3, 1e-3).dpsi, -1.0, 1e-6);
  EXPECT_NEAR(arctan_potential(1e3, 1e-3).psi / 1e3, 1.0, 1e-4);
  EXPECT_EQ(arctan_potential(0.0, 1e-3).psi, 0.0);
}

namespace {

struct Capture : TermSink {
  double energy = 0;
  std::vector<Vec2> grad;
  std::vector<Eigen::Matrix2d> hess;
  explicit Capture(std::size_t n) : grad(n, Vec2::Zero()), hess(n, Eigen::Matrix2d::Zero()) {}
  void add(const Index* nodes, int k, double e, const double* g, const double* H) override {
    ASSERT_EQ(k, 1);
    energy += e;
    grad[nodes[0]] += Vec2(g[0], g[1]);
    hess[nodes[0]] += Eigen::Map<const Eigen::Matrix2d>(H);
  }
};

// A flat die along y = 10 (walked left to right: normal -y), moving at
// (0.3, -1) mm/s, and the top face of a body: nodes at x = 0, 1, ..., 10.
struct FlatContact {
  std::vector<Die> dies;                       // the one die
  std::vector<Vec2> x;                         // node coordinates
  std::vector<ContactNode> nodes;              // all in contact
  std::vector<ContactEdge> edges;              // between neighbours
  std::vector<double> flow_stress;             // per element
  StepView view;
  explicit FlatContact(FrictionLaw law, Geometry g = Geometry::Axisymmetric) {
    Die d;
    d.name = "die";
    d.profile = DieProfile({Vec2(-1, 10), Vec2(30, 10)}, {});
    d.motion = DieMotion(Vec2(0.3, -1.0));
    d.friction = law;
    dies.push_back(d);
    for (int i = 0; i <= 10; ++i) {
      x.emplace_back(i, 10.0);
      ContactNode c;
      c.node = i;
      c.in_contact = true;
      c.proj = dies[0].project(x.back(), 0.0);
      nodes.push_back(c);
      if (i > 0) edges.push_back({i - 1, i, i - 1});
    }
    flow_stress.assign(10, 300.0);
    view.x = &x;
    view.flow_stress = &flow_stress;
    view.geometry = g;
  }
};

}  // namespace

TEST(ContactFriction, ContactAreaAndBoundsOfBothLaws) {
  FrictionLaw factor;
  factor.kind = FrictionLaw::Kind::Factor;
  factor.m = 0.4;
  FlatContact c(factor);
  ContactFriction f(c.dies, 1.0);
  f.update_weights(c.view, c.edges, c.nodes);
  double area = 0, bound = 0;
  f.update_bounds(c.nodes);
  for (const auto& n : c.nodes) area += n.weight, bound += n.bound;
  EXPECT_NEAR(area, kPi * 100, 1e-9);                                // pi R^2 of the face
  EXPECT_NEAR(bound, 0.4 * 300 / std::sqrt(3.0) * kPi * 100, 1e-6);  // m k A
  // A node whose neighbour left the die loses that edge's area.
  c.nodes[10].in_contact = false;
  f.update_weights(c.view, c.edges, c.nodes);
  EXPECT_NEAR(c.nodes[9].weight, 2 * kPi * 1 * (2 * 9 + 8) / 6.0, 1e-12);

  FrictionLaw coulomb;
  coulomb.kind = FrictionLaw::Kind::Coulomb;
  coulomb.mu = 0.2;
  FlatContact d(coulomb, Geometry::PlaneStrain);
  ContactFriction g(d.dies, 1.0);
  g.update_weights(d.view, d.edges, d.nodes);
  d.nodes[3].normal_force = 50.0;   // mu N = 10 < k w = 173.2
  d.nodes[4].normal_force = 5000.0;  // capped at k w (sticking)
  d.nodes[5].normal_force = -1.0;    // tension: no friction
  g.update_bounds(d.nodes);
  EXPECT_NEAR(d.nodes[3].bound, 10.0, 1e-12);
  EXPECT_NEAR(d.nodes[4].bound, 300 / std::sqrt(3.0) * 1.0, 1e-12);
  EXPECT_EQ(d.nodes[5].bound, 0.0);
  // The fixed point measures its own change.
  d.nodes[3].normal_force = 100.0;
  EXPECT_NEAR(g.update_bounds(d.nodes), 10.0 / (300 / std::sqrt(3.0)), 1e-12);
  EXPECT_EQ(g.update_bounds(d.nodes), 0.0);
}

TEST(ContactFriction, TermsMatchFiniteDifferences) {
  FrictionLaw law;
  law.kind = FrictionLaw::Kind::Factor;
  law.m = 0.7;
  law.a_relative = 1e-2;
  FlatContact c(law);
  ContactFriction f(c.dies, 1.0);
  while (f.relax_smoothing()) {}
  EXPECT_NEAR(f.smoothing_speed(0), 1e-2, 1e-15);
  f.update_weights(c.view, c.edges, c.nodes);
  f.update_bounds(c.nodes);
  // Sliding speeds relative to the die from -0.5 to 0.5 mm/s, several of
  // them inside the smoothing band |s| < a.
  std::vector<Vec2> v;
  for (int i = 0; i <= 10; ++i) v.emplace_back(0.3 + 0.1 * (i - 5) * (i % 3 == 0 ? 0.01 : 1.0), -1.0 + 0.05 * i);
  Capture at(v.size());
  f.add_terms(c.view, v, c.nodes, at);
  for (int i = 0; i <= 10; ++i)
    for (int k = 0; k < 2; ++k) {
      const double h = 1e-6;
      std::vector<Vec2> vp = v, vm = v;
      vp[i](k) += h;
      vm[i](k) -= h;
      Capture p(v.size()), m(v.size());
      f.add_terms(c.view, vp, c.nodes, p);
      f.add_terms(c.view, vm, c.nodes, m);
      const double scale = std::max(1.0, at.grad[i].norm());
      EXPECT_NEAR(at.grad[i](k), (p.energy - m.energy) / (2 * h), 1e-6 * scale) << i << "," << k;
      const Vec2 dg = (p.grad[i] - m.grad[i]) / (2 * h);
      const double hs = std::max(1.0, at.hess[i].norm());
      EXPECT_NEAR(at.hess[i](0, k), dg(0), 1e-5 * hs) << i;
      EXPECT_NEAR(at.hess[i](1, k), dg(1), 1e-5 * hs) << i;
    }
  // The friction force opposes the sliding relative to the die, and is
  // bounded by the node's m k w.
  f.record(c.view, v, c.nodes);
  for (const auto& n : c.nodes) {
    EXPECT_LE(n.friction.dot(Vec2(n.slip, 0)), 0.0);
    EXPECT_LE(n.friction.norm(), n.bound * (1 + 1e-12));
  }
}
