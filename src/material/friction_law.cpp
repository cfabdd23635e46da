#include "material/friction_law.hpp"

#include <cmath>
#include <cstdio>

#include "core/types.hpp"

namespace rpfem {

std::string FrictionLaw::describe() const {
  char buf[96];
  switch (kind) {
    case Kind::None: return "frictionless";
    case Kind::Factor: std::snprintf(buf, sizeof buf, "friction factor m = %g", m); break;
    case Kind::Coulomb: std::snprintf(buf, sizeof buf, "Coulomb mu = %g", mu); break;
  }
  std::string out = buf;
  if (treatment == Treatment::Exact) return out + ", exact";
  std::snprintf(buf, sizeof buf, ", a = %g", a_relative);
  return out + buf + (treatment == Treatment::Arctan ? " (arctan)" : "");
}

ArctanPotential arctan_potential(double s, double a) {
  const double r = s / a;
  ArctanPotential p;
  p.dpsi = 2 / kPi * std::atan(r);
  // log1p keeps psi accurate for |s| << a, where psi ~ s^2 / (pi a).
  p.psi = 2 / kPi * (s * std::atan(r) - 0.5 * a * std::log1p(r * r));
  p.d2psi = 2 / kPi * (1 / a) / (1 + r * r);
  return p;
}

}  // namespace rpfem
