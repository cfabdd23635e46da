// Step control by a local error estimate (stepping.tolerance): the
// embedded pair explicit Euler (order 1) / midpoint (order 2) of the
// updated-Lagrangian update (model/stepper.hpp). Over a step of length dt
// from the state (x, eps) with the velocity v0 solved there and v_half
// solved at the half step,
//
//   x_E = x + dt v0,        eps_E = eps + dt epsdot0        (Euler)
//   x_M = x + dt v_half,    eps_M = eps + dt epsdot_half    (midpoint)
//
// and x_M - x_E = dt (v_half - v0) = (dt^2 / 2) x'' + O(dt^3) is Euler's
// local error to leading order (Hairer, Norsett, Wanner, "Solving ODEs I",
// 2nd ed., sec. II.4, embedded formulas). The estimate is stated in the
// quantities the press load is made of, a flow stress times an area,
// relative:
//
//   e = max( max_nodes |x_M - x_E| / L,
//            sum_e ( <|s(eps_M) - s(eps_E)|>_e V_e(x_M)
//                    + <s(eps_M)>_e |V_e(x_M) - V_e(x_E)| )
//            / sum_e <s(eps_M)>_e V_e(x_M) )                            (1)
//
// with L the bodies' size (the reference length), s the point's flow
// stress law at the strain, <.>_e the mean over the element's 2x2 points
// and V_e its volume (per unit depth in plane strain): the relative error
// of the sum of flow stress times volume, a load's measure, is at most
// the second term (docs/theory.md, "Step control").
// The tolerance is an error per unit stroke (HNW II.4, "error per unit
// step"): a step of increment ds is accepted when e <= tol ds / S, S the
// end stroke, so the local errors of a run add up to at most tol over the
// stroke; the next increment is
//
//   ds_new = ds min(fac_max, max(fac_min, fac (tol ds / (S e))^(1/q)))   (2)
//
// with q = 1 (e ~ ds^2 against a bound ~ ds), HNW II.4 eq. (4.13) for the
// error per unit step.
#pragma once
#include <array>
#include <vector>

#include "core/types.hpp"
#include "mesh/mesh.hpp"
#include "model/element_material.hpp"

namespace rpfem {

// The constants of (2): the safety factor and the bounds of one change
// (HNW II.4: fac 0.8 to 0.9, facmax 1.5 to 5; after a rejection at most 1).
struct StepControlFactors {
  double safety = 0.9;
  double fac_min = 0.2;
  double fac_max = 2.0;
};

// Estimate (1). x: the start's coordinates (mm) on mesh m; dt: the step's
// length (s); v0, v_half: the start's and the half step's velocity (mm/s);
// eps: the start's strain at the 2x2 points, rate0, rate_half the rates
// there; material[e]: element e's (its flow stress law); length: L (mm).
double step_error_estimate(const Mesh& m, Geometry g, const std::vector<Vec2>& x, double dt,
                           const std::vector<Vec2>& v0, const std::vector<Vec2>& v_half,
                           const std::vector<std::array<double, 4>>& eps,
                           const std::vector<std::array<double, 4>>& rate0,
                           const std::vector<std::array<double, 4>>& rate_half,
                           const std::vector<ElementMaterial>& material, double length);

// The bound of the estimate for a step of increment ds (mm): tol ds / S.
inline double step_error_bound(double tolerance, double ds, double end_stroke) { return tolerance * ds / end_stroke; }

// The next increment (2), mm, from a step of increment ds with estimate e
// against its bound, the change bounded relative to base (ds, or the
// increment proposed for a step that a landing ended short); rejected:
// the step is redone, never longer than base.
double next_increment(double ds, double estimate, double bound, double base, bool rejected,
                      const StepControlFactors& f = {});

}  // namespace rpfem
