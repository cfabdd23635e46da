// One element's share of the rigid-plastic functional (paper eq. 2):
//
//   Pi_e = int phi(epsdot_bar) dV + (alpha/2) int epsdot_v^2 dV
//
// phi' = sigma_bar (material/flow_stress.hpp). epsdot_bar^2 = eps^T P eps is
// the effective rate of the deviatoric strain rate,
// (2/3) e'_ij e'_ij, integrated with 2x2 Gauss points; the volumetric penalty
// on the element's mean dilatation, (alpha/2) V (mean epsdot_v)^2 (Nagtegaal,
// Parks and Rice 1974; Hughes 1980), so the element does not lock. It is the
// 1-point rule of selective reduced integration (Kobayashi, Oh, Altan 1989,
// sec. 7.3) for a parallelogram in plane strain; in axisymmetry the mean
// differs from the centre value.
#pragma once
#include <array>
#include <cmath>

#include "fem/quad4.hpp"
#include "material/flow_stress.hpp"

namespace rpfem {

struct RigidPlasticInput {
  Quad4Coords X;                  // node coordinates, mm
  Vec8 v;                         // node velocities, mm/s
  std::array<double, 4> strain{};  // effective strain at the 2x2 points
  const FlowStressLaw* law = nullptr;
  // MPa: law->yield(strain[q]) where the caller has it (a step's strains
  // are fixed, and an element pass would take the power anew at every
  // point); NaN: taken here.
  std::array<double, 4> yield{NAN, NAN, NAN, NAN};
  Geometry geometry = Geometry::Axisymmetric;
  double alpha = 0;       // volumetric penalty, MPa s
  double epsdot_lim = 0;  // limiting strain rate, 1/s
  // Cold-start predictor: when > 0, every point is linear-viscous with the
  // viscosity sigma_bar(r)/r at r = viscous_floor, so the first solve from
  // v = 0 is a Stokes-like solve at a realistic viscosity (1/s; 0 = off, the
  // material law proper).
  double viscous_floor = 0;
  // Viscous regularization (s): adds (c/2) epsdot_bar^2 with
  // c = regularization * sigma_y(eps) to the dissipation density. The
  // rate-independent functional is homogeneous of degree one and may have a
  // flat set of minimizers (Hill's non-uniqueness in plane strain); a small
  // c makes it strictly convex and selects one, changing the stress by the
  // relative amount regularization * epsdot_bar.
  double regularization = 0;
};

enum class Tangent {
  None,        // gradient only
  Consistent,  // exact Hessian of Pi_e (Newton-Raphson)
  Secant,      // (sigma_bar/epsdot_bar) B^T P B only (direct iteration)
};

struct ElementTerms {
  double energy = 0;  // Pi_e, N mm/s
  Vec8 grad;          // dPi_e/dv, N
  Mat8 hess;          // d^2 Pi_e/dv^2, N s/mm
};

// Energy only (line search).
double rigid_plastic_energy(const RigidPlasticInput& in);
// Energy, gradient and (unless Tangent::None) the Hessian or secant matrix.
void rigid_plastic_terms(const RigidPlasticInput& in, Tangent t, ElementTerms& out);

// What a step records per element.
struct ElementPost {
  std::array<double, 4> strain_rate{};  // effective strain rate at the 2x2 points
  double strain_rate_mean = 0;          // volume-weighted mean
  double volumetric_rate = 0;           // the element's mean epsdot_v
  double mean_stress = 0;               // sigma_m = alpha epsdot_v, MPa
  double volume = 0;                    // mm^3 (2 pi r included in axisymmetry)
  double min_detJ = 0;                  // at the 2x2 points and the centre
};
ElementPost rigid_plastic_post(const RigidPlasticInput& in);

// The deviatoric metric: epsdot_bar^2 = eps^T P eps for eps = (e11, e22,
// e33, gamma12): P = (2/3)(I - 11^T/3) on the normal rates, 1/3 on gamma.
const Eigen::Matrix4d& effective_rate_metric();

}  // namespace rpfem
