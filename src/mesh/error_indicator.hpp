// A posteriori estimate of the strain-rate error by recovery (Zienkiewicz
// and Zhu, IJNME 33 (1992) 1331-1364, superconvergent patch recovery;
// the ZZ estimator, IJNME 24 (1987) 337-357). The effective strain rate at
// the 2x2 points, epsdot_h, is recovered to the nodes by the patch planes
// of mesh/field_transfer.hpp (recover_at_nodes), interpolated back with
// the shape functions, epsdot* = sum_a N_a epsdot*_a, and per element
//
//   eta_e^2 = int_e (epsdot* - epsdot_h)^2 dV         (2x2 Gauss points)
//
// (dV = 2 pi r dA in axisymmetry). The global relative estimate is
//
//   eta = sqrt(sum_e eta_e^2) / ||epsdot_h||_L2.
//
// The element's field is the error's root mean square over it,
// eta_e / sqrt(V_e) (1/s), comparable between elements of any size
// (docs/theory.md, "Strain-rate error indicator").
#pragma once
#include <array>
#include <vector>

#include "core/types.hpp"
#include "mesh/mesh.hpp"

namespace rpfem {

struct StrainRateError {
  std::vector<double> element_rms;  // 1/s, eta_e / sqrt(V_e) per element
  std::vector<double> element_eta;  // eta_e per element (1/s mm^(3/2), per mm of
                                    // depth in plane strain)
  double relative = 0;              // eta / ||epsdot_h||_L2 (0 where the rate is zero everywhere)
  double rate_norm = 0;             // ||epsdot_h||_L2 (1/s mm^(3/2), as element_eta)
};

// rate: the effective strain rate at the 2x2 points of each element of m
// at coordinates x.
StrainRateError strain_rate_error(const Mesh& m, const std::vector<Vec2>& x,
                                  const std::vector<std::array<double, 4>>& rate, Geometry g);

}  // namespace rpfem
