#include "mms.hpp"

#include <cmath>

#include "mesh/error_indicator.hpp"
#include "fem/quad4.hpp"
#include "fem/rigid_plastic_element.hpp"
#include "mesh/generate.hpp"
#include "model/step_problem.hpp"
#include "none/no_contact.hpp"

namespace rpfem {

namespace {

constexpr double kA = 1.0, kEps = 0.02, kK = 100.0;  // 1/s, -, MPa
constexpr double k1 = kPi, c1 = 0.3, k2 = 1.3 * kPi, c2 = 0.5;

// S(x) T(y) and derivatives.
struct Wave {
  double S, S1, S2, T, T1, T2;
};
Wave wave(double x, double y) {
  return {std::sin(k1 * x + c1), k1 * std::cos(k1 * x + c1), -k1 * k1 * std::sin(k1 * x + c1),
          std::sin(k2 * y + c2), k2 * std::cos(k2 * y + c2), -k2 * k2 * std::sin(k2 * y + c2)};
}

struct Exact {
  Vec2 v;
  Eigen::Matrix2d grad;  // grad(i, j) = d v_i / d x_j
};

Exact exact(Geometry g, const Vec2& p) {
  const double x = p(0), y = p(1);
  const Wave w = wave(x, y);
  Exact e;
  if (g == Geometry::PlaneStrain) {
    // psi = a x y + eps S T; v = (psi_y, -psi_x).
    e.v = Vec2(kA * x + kEps * w.S * w.T1, -kA * y - kEps * w.S1 * w.T);
    e.grad << kA + kEps * w.S1 * w.T1, kEps * w.S * w.T2, -kEps * w.S2 * w.T, -kA - kEps * w.S1 * w.T1;
  } else {
    // psi = r^2 phi, phi = -a z/2 + eps S(r) T(z); v_r = -r phi_z, v_z = 2 phi + r phi_r.
    const double r = x;
    const double phi = -0.5 * kA * y + kEps * w.S * w.T, phr = kEps * w.S1 * w.T, phz = -0.5 * kA + kEps * w.S * w.T1;
    const double phrr = kEps * w.S2 * w.T, phrz = kEps * w.S1 * w.T1, phzz = kEps * w.S * w.T2;
    e.v = Vec2(-r * phz, 2 * phi + r * phr);
    e.grad << -phz - r * phrz, -r * phzz, 3 * phr + r * phrr, 2 * phz + r * phrz;
  }
  return e;
}

// Deviatoric stress (s_11, s_22, s_33, s_12) of the exact field.
Eigen::Vector4d stress(Geometry g, const Vec2& p) {
  const Exact e = exact(g, p);
  Eigen::Vector4d eps(e.grad(0, 0), e.grad(1, 1), g == Geometry::Axisymmetric ? e.v(0) / p(0) : 0.0,
                      e.grad(0, 1) + e.grad(1, 0));
  const double rate = std::sqrt(eps.dot(effective_rate_metric() * eps));
  const double tr = eps(0) + eps(1) + eps(2);
  const double c = (2.0 / 3.0) * kK / rate;
  return {c * (eps(0) - tr / 3), c * (eps(1) - tr / 3), c * (eps(2) - tr / 3), 0.5 * c * eps(3)};
}

// f = -div s (Cartesian, or cylindrical with the hoop terms).
Vec2 body_force(Geometry g, const Vec2& p) {
  const double h = 1e-5;
  const Vec2 dx(h, 0), dy(0, h);
  const Eigen::Vector4d sxp = stress(g, p + dx), sxm = stress(g, p - dx), syp = stress(g, p + dy),
                        sym = stress(g, p - dy);
  Vec2 div((sxp(0) - sxm(0)) / (2 * h) + (syp(3) - sym(3)) / (2 * h),
           (sxp(3) - sxm(3)) / (2 * h) + (syp(1) - sym(1)) / (2 * h));
  if (g == Geometry::Axisymmetric) {
    const Eigen::Vector4d s = stress(g, p);
    div += Vec2((s(0) - s(2)) / p(0), s(3) / p(0));
  }
  return -div;
}

constexpr double kG3[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
constexpr double kW3[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

// Calls f(e, p, xp, w) at each 3 x 3 Gauss point of every element: its
// shape functions p, position xp and volume weight w.
template <class F>
void for_each_gauss_point(const Mesh& mesh, Geometry g, F&& f) {
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    Quad4Coords X;
    for (int a = 0; a < 4; ++a) X[a] = mesh.x[mesh.quads[e][a]];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Quad4Point p = quad4_point(X, kG3[i], kG3[j]);
        Vec2 xp = Vec2::Zero();
        for (int a = 0; a < 4; ++a) xp += p.N(a) * X[a];
        f(e, p, xp, volume_weight(p, g, kW3[i] * kW3[j]));
      }
  }
}

// The exact field's body force as nodal forces.
std::vector<Vec2> nodal_body_forces(const Mesh& mesh, Geometry g) {
  std::vector<Vec2> fext(mesh.x.size(), Vec2::Zero());
  for_each_gauss_point(mesh, g, [&](Index e, const Quad4Point& p, const Vec2& xp, double w) {
    const Vec2 f = body_force(g, xp);
    for (int a = 0; a < 4; ++a) fext[mesh.quads[e][a]] += w * p.N(a) * f;
  });
  return fext;
}

// The exact velocity prescribed at every boundary node.
std::vector<NodeConstraint> exact_boundary_velocities(const Mesh& mesh, Geometry g) {
  std::vector<NodeConstraint> cons;
  for (Index i : mesh.side_nodes("mms.boundary")) {
    const Vec2 v = exact(g, mesh.x[i]).v;
    cons.push_back({i, Vec2(1, 0), v(0)});
    cons.push_back({i, Vec2(0, 1), v(1)});
  }
  return cons;
}

// ||v_h - v|| / ||v|| in L2 over the mesh.
double relative_l2_error(const Mesh& mesh, Geometry g, const std::vector<Vec2>& v) {
  double err2 = 0, ref2 = 0;
  for_each_gauss_point(mesh, g, [&](Index e, const Quad4Point& p, const Vec2& xp, double w) {
    Vec2 vh = Vec2::Zero();
    for (int a = 0; a < 4; ++a) vh += p.N(a) * v[mesh.quads[e][a]];
    const Vec2 ve = exact(g, xp).v;
    err2 += w * (vh - ve).squaredNorm();
    ref2 += w * ve.squaredNorm();
  });
  return std::sqrt(err2 / ref2);
}

// The effective strain rate sqrt(e . M e) of the rates e = (e_11, e_22,
// e_33, gamma_12).
double effective_rate(const Eigen::Vector4d& e) { return std::sqrt(e.dot(effective_rate_metric() * e)); }

// The effective rate of v at point p of element e.
double discrete_rate(const Mesh& mesh, Geometry g, Index e, const Quad4Point& p, const std::vector<Vec2>& v) {
  Vec8 ve;
  for (int a = 0; a < 4; ++a) ve.segment<2>(2 * a) = v[mesh.quads[e][a]];
  return effective_rate(strain_rate_matrix(p, g) * ve);
}

// || epsdot(v) - epsdot(v*) || / || epsdot(v*) || in L2 over the mesh.
double relative_rate_error(const Mesh& mesh, Geometry g, const std::vector<Vec2>& v) {
  double err2 = 0, ref2 = 0;
  for_each_gauss_point(mesh, g, [&](Index e, const Quad4Point& p, const Vec2& xp, double w) {
    const Exact ex = exact(g, xp);
    const Eigen::Vector4d rate(ex.grad(0, 0), ex.grad(1, 1), g == Geometry::Axisymmetric ? ex.v(0) / xp(0) : 0.0,
                               ex.grad(0, 1) + ex.grad(1, 0));
    const double exact_rate = effective_rate(rate);
    const double d = discrete_rate(mesh, g, e, p, v) - exact_rate;
    err2 += w * d * d;
    ref2 += w * exact_rate * exact_rate;
  });
  return std::sqrt(err2 / ref2);
}

// The recovery-based estimate of the same from the rates at the 2x2 points.
double rate_error_estimate(const Mesh& mesh, Geometry g, const std::vector<Vec2>& v) {
  std::vector<std::array<double, 4>> rate(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    Quad4Coords X;
    for (int a = 0; a < 4; ++a) X[a] = mesh.x[mesh.quads[e][a]];
    for (int q = 0; q < 4; ++q) rate[e][q] = discrete_rate(mesh, g, e, quad4_gauss_point(X, q), v);
  }
  return strain_rate_error(mesh, mesh.x, rate, g).relative;
}

}  // namespace

MmsResult run_mms(Geometry g, int n) {
  RectangleSpec spec;
  spec.nx = spec.ny = n;
  const Mesh mesh = make_rectangle("mms", spec);
  FlowStressLaw law;
  law.K = kK;
  law.n = 0.0;
  std::vector<ElementMaterial> mats(mesh.num_elements(), ElementMaterial{&law, 1e7 * kK / kA});
  std::vector<std::array<double, 4>> strain(mesh.num_elements(), {0, 0, 0, 0});
  std::vector<double> flow(mesh.num_elements(), kK);
  StepView view;
  view.mesh = &mesh;
  view.x = &mesh.x;
  view.flow_stress = &flow;
  view.geometry = g;

  const std::vector<Vec2> fext = nodal_body_forces(mesh, g);
  const std::vector<NodeConstraint> cons = exact_boundary_velocities(mesh, g);
  NoContact none;
  SolverWorkspace ws(LinearSolverChoice::Auto);
  StepProblem problem(view, strain, mats, 1e-6 * kA, fext, none, ws);
  problem.set_constraints(cons);
  Vec u = Vec::Zero(problem.dofs().num_free());
  problem.viscous_predictor(kA, u);
  NewtonSettings ns;
  ns.tol_velocity = 1e-12;
  ns.tol_force = 1e-9;  // the round-off floor is ~2e-10 at n = 32
  ns.max_iterations = 60;
  const NewtonResult nr = newton_solve(problem.newton_system(), ns, u);
  std::vector<Vec2> v;
  problem.dofs().expand(u, v);

  MmsResult r;
  r.n = n;
  r.h = 1.0 / n;
  r.l2_error = relative_l2_error(mesh, g, v);
  r.strain_rate_error = relative_rate_error(mesh, g, v);
  r.strain_rate_estimate = rate_error_estimate(mesh, g, v);
  r.newton_iterations = nr.iterations;
  r.converged = nr.converged;
  return r;
}

std::vector<double> observed_orders(const std::vector<MmsResult>& r) {
  std::vector<double> p;
  for (std::size_t i = 1; i < r.size(); ++i)
    p.push_back(std::log(r[i - 1].l2_error / r[i].l2_error) / std::log(r[i - 1].h / r[i].h));
  return p;
}

}  // namespace rpfem
