// The homogeneous compression of a stack between frictionless platens (the
// contact patch test): the exact flow is uniform over the stack of current
// height H, the bottom platen fixed and the top one moving down at v:
//   v_y = -v (y - y_bottom) / H,
//   axisymmetric:  v_r = v r / (2 H),  effective strain rate v / H
//   plane strain:  v_x = v (x - x_c) / H,  effective strain rate 2 v / (sqrt(3) H)
// (Kobayashi, Oh, Altan 1989, sec. 2.4 with sec. 5.2's effective rate). The
// plane-strain velocity is exact up to a rigid translation in x, which the
// comparison removes (x_c is fitted), so only the strain rate is compared there.
#pragma once
#include <string>

#include "core/types.hpp"

namespace rpfem {

struct HomogeneousFlowError {
  double strain_rate = 0;       // max over elements |e / e_exact - 1|
  double strain_rate_l2 = 0;    // ||e - e_exact|| / ||e_exact||, over elements
  double velocity = 0;          // axisymmetric: max over nodes |v - v_exact| / v
  double height = 0;            // mm, H at the step
  double exact_rate = 0;        // 1/s
  int elements = 0;
};

// At recorded step `step` of result.h5, for the top platen speed v (mm/s).
HomogeneousFlowError homogeneous_flow_error(const std::string& h5, int step, double platen_speed, Geometry g);

}  // namespace rpfem
