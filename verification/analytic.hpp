// Closed-form references.
#pragma once
#include "material/flow_stress.hpp"

namespace rpfem {

// sigma_bar at strain eps and effective strain rate rate (with the law's
// optional rate term).
double flow_stress(const FlowStressLaw& law, double eps, double rate);

// Homogeneous frictionless upsetting of a cylinder of initial diameter D0,
// height H0 to height H (Kobayashi, Oh, Altan 1989, sec. 5.2):
// eps = ln(H0/H), F = sigma_bar(eps) A0 H0 / H (N).
double upsetting_load_axisymmetric(const FlowStressLaw& law, double D0, double H0, double H, double rate = 1);

// Plane strain block of width w0, per unit depth (N/mm):
// eps = (2/sqrt 3) ln(H0/H), F = (2/sqrt 3) sigma_bar(eps) w0 H0 / H.
// rate: the effective strain rate (only used by a rate-sensitive law).
double upsetting_load_plane_strain(const FlowStressLaw& law, double w0, double H0, double H, double rate = 1);
double upsetting_strain_plane_strain(double H0, double H);

}  // namespace rpfem

namespace rpfem {

// Slab-method average die pressure over the flow stress for a cylinder of
// radius R and full height H upset with friction factor m (Kobayashi, Oh,
// Altan 1989, sec. 4.3; Avitzur): p_avg / sigma_bar = 1 + 2 m R / (3 sqrt(3) H).
// It assumes homogeneous deformation with friction along the whole face
// (no barrelling, no sticking zone).
double slab_upsetting_pressure_ratio(double m, double R, double H);

// Ring compression with frictionless dies (homogeneous deformation, volume
// conserved): every radius scales as sqrt(H0/H), so the inner diameter
// changes by sqrt(H0/H) - 1 (a fraction, positive: the hole grows; as a
// decrease, "1 - sqrt(H0/H)", it has the same magnitude).
double ring_inner_diameter_change_frictionless(double H0, double H);

}  // namespace rpfem
