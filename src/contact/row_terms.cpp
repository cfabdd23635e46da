#include "contact/row_terms.hpp"

#include <algorithm>

namespace rpfem {

double friction_bound(const FrictionLaw& law, bool in_contact, double N, double kw) {
  if (!in_contact) return 0;
  switch (law.kind) {
    case FrictionLaw::Kind::Factor: return law.m * kw;                         // tau = m k
    case FrictionLaw::Kind::Coulomb: return std::min(law.mu * std::max(N, 0.0), kw);  // tau = min(mu p, k)
    case FrictionLaw::Kind::None: break;
  }
  return 0;
}

RowTerm row_term(const PairKinematics& p, const RowLaw& law, const std::vector<Vec2>& vel) {
  RowTerm out;
  const Vec2 t(-p.n(1), p.n(0));
  Vec2 u = -p.offset;
  for (int a = 0; a < p.k; ++a) u += p.c[a] * vel[p.nodes[a]];
  out.gamma_n = u.dot(p.n);
  out.gamma_t = u.dot(t);

  double dB = 0;  // dB / d gamma_N
  if (law.normal) {
    // Normal (paper eq. 7-8): N = max(0, lambda - beta r) one-sided.
    const double r = out.gamma_n + p.gap_from * law.inv_dt;
    const double shifted = law.one_sided ? r - law.lambda / law.beta : r;
    const bool pressing = !law.one_sided || shifted < 0;
    if (pressing) {
      out.normal_force = -law.beta * shifted;
      out.energy = 0.5 * law.beta * shifted * shifted;
      out.dE_dn = law.beta * shifted;
    }
    constexpr double kLifted = 1e-12;  // RowLaw::keep_stiffness
    out.H_nn = pressing || shifted == 0 ? law.beta : law.keep_stiffness ? kLifted * law.beta : 0.0;
  }

  // Friction (paper eq. 11-12).
  if (law.fixed_bound >= 0) {
    out.bound = law.fixed_bound;
  } else {
    out.bound = friction_bound(FrictionLaw{law.kind, law.m, law.mu}, true, out.normal_force, law.k_weight);
    // Coulomb below the sticking cap: B = mu N(gamma_N).
    if (law.kind == FrictionLaw::Kind::Coulomb && out.normal_force > 0 && law.mu * out.normal_force < law.k_weight)
      dB = -law.mu * law.beta;
  }
  const double energy_bound = law.merit_bound >= 0 ? law.merit_bound : out.bound;
  if (out.bound <= 0 && dB == 0 && energy_bound <= 0) return out;
  const ArctanPotential f = arctan_potential(out.gamma_t, law.a);
  out.energy += energy_bound * f.psi;
  out.friction = -out.bound * f.dpsi;
  out.dE_dt = out.bound * f.dpsi;
  out.H_tt = out.bound * f.d2psi;
  out.H_tn = f.dpsi * dB;
  return out;
}

void expand(const PairKinematics& p, const RowTerm& t, double* grad, double* hess) {
  const int nd = 2 * p.k;
  const Vec2 tan(-p.n(1), p.n(0));
  // d gamma_N / dV = c (x) n,  d gamma_T / dV = c (x) t.
  std::array<double, 2 * kMaxRowNodes> dn, dt;
  for (int a = 0; a < p.k; ++a)
    for (int i = 0; i < 2; ++i) dn[2 * a + i] = p.c[a] * p.n(i), dt[2 * a + i] = p.c[a] * tan(i);
  for (int i = 0; i < nd; ++i) grad[i] = t.dE_dn * dn[i] + t.dE_dt * dt[i];
  if (!hess) return;
  for (int j = 0; j < nd; ++j)
    for (int i = 0; i < nd; ++i)
      hess[j * nd + i] = t.H_nn * (dn[i] * dn[j]) + t.H_tt * (dt[i] * dt[j]) + t.H_tn * (dt[i] * dn[j]);
}

void add_row_term(TermSink& sink, const PairKinematics& p, const RowTerm& t) {
  std::array<double, 2 * kMaxRowNodes> grad;
  std::array<double, 4 * kMaxRowNodes * kMaxRowNodes> hess;
  const bool h = sink.needs_hessian();
  expand(p, t, grad.data(), h ? hess.data() : nullptr);
  sink.add(p.nodes.data(), p.k, t.energy, grad.data(), hess.data());
}

}  // namespace rpfem
