#include "ipopt/friction_bounds.hpp"

#include <algorithm>

namespace rpfem {

FrictionTerm friction_term(const PairKinematics& k, double bound, double a, const std::array<Vec2, 3>& v) {
  FrictionTerm out;
  const Vec2 t(-k.n(1), k.n(0));
  Vec2 u = -k.offset;
  for (int i = 0; i < k.k; ++i) u += k.c[i] * v[i];
  const ArctanPotential f = arctan_potential(u.dot(t), a);  // paper eq. 11-12
  std::array<double, 6> dt{};
  for (int i = 0; i < k.k; ++i) dt[2 * i] = k.c[i] * t(0), dt[2 * i + 1] = k.c[i] * t(1);
  const int nd = 2 * k.k;
  out.energy = bound * f.psi;
  for (int i = 0; i < nd; ++i) out.grad[i] = bound * f.dpsi * dt[i];
  for (int j = 0; j < nd; ++j)
    for (int i = 0; i < nd; ++i) out.hess[j * nd + i] = bound * f.d2psi * (dt[i] * dt[j]);  // exactly symmetric
  return out;
}

double friction_bound(const FrictionLaw& law, double N, double kw) {
  if (!(N > 0)) return 0;
  switch (law.kind) {
    case FrictionLaw::Kind::Factor: return law.m * kw;
    case FrictionLaw::Kind::Coulomb: return std::min(law.mu * N, kw);
    case FrictionLaw::Kind::None: break;
  }
  return 0;
}

}  // namespace rpfem
