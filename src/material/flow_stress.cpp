#include "material/flow_stress.hpp"

#include <array>
#include <cmath>

namespace rpfem {

double FlowStressLaw::yield(double eps_bar) const { return K * std::pow(eps0 + eps_bar, n); }

FlowPoint flow_point(const FlowStressLaw& law, double eps_bar, double epsdot, double epsdot_lim) {
  return flow_point_at_yield(law, law.yield(eps_bar), epsdot, epsdot_lim);
}

FlowPoint flow_point_at_yield(const FlowStressLaw& law, double sy, double epsdot, double epsdot_lim) {
  // Rate factor g(r) = (r/rate_ref)^m and its integral G(r) = int_0^r g.
  auto g = [&](double r) { return law.m == 0 ? 1.0 : std::pow(r / law.rate_ref, law.m); };
  auto G = [&](double r) {
    return law.m == 0 ? r : law.rate_ref / (law.m + 1) * std::pow(r / law.rate_ref, law.m + 1);
  };
  const double s_lim = sy * g(epsdot_lim);
  FlowPoint p;
  if (epsdot < epsdot_lim) {
    // Linear viscous: sigma = s_lim r / r_lim, phi = s_lim r^2 / (2 r_lim).
    p.rigid = true;
    p.sigma = s_lim * epsdot / epsdot_lim;
    p.dsigma = s_lim / epsdot_lim;
    p.phi = 0.5 * s_lim * epsdot * epsdot / epsdot_lim;
    return p;
  }
  p.sigma = sy * g(epsdot);
  p.dsigma = law.m == 0 ? 0.0 : law.m * p.sigma / epsdot;
  // phi continuous at r_lim: phi(r_lim) = s_lim r_lim / 2.
  p.phi = 0.5 * s_lim * epsdot_lim + sy * (G(epsdot) - G(epsdot_lim));
  return p;
}

namespace {
// Paper Table 1 (eq. 13 fitted on strains 0.1-0.7); the virtual rigid body
// of the paper's Test II.
const std::array<LibraryMaterial, 3> kLibrary{{
    {"AISI1010", "Jang & Hwang 2002, Table 1", 72.98, 0.22},
    {"AISI1035", "Jang & Hwang 2002, Table 1", 91.97, 0.17},
    {"VIRTUAL_RIGID", "Jang & Hwang 2002, Test II", 1.0e5, 1.0e-4},
}};
}  // namespace

const LibraryMaterial* find_library_material(const std::string& name) {
  for (const auto& m : kLibrary)
    if (m.name == name) return &m;
  return nullptr;
}

std::string library_material_names() {
  std::string s;
  for (const auto& m : kLibrary) s += (s.empty() ? "" : ", ") + m.name;
  return s;
}

}  // namespace rpfem
