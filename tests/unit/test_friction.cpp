// The arctan friction law (paper eq. 11-12): the potential's derivatives
// against finite differences and its limits.
#include <gtest/gtest.h>

#include <cmath>

#include "material/friction_law.hpp"

using namespace rpfem;

TEST(ArctanPotential, DerivativesMatchFiniteDifferences) {
  const double a = 1e-3;
  for (double s : {-3.0, -2e-3, -1e-4, 0.0, 5e-5, 1e-3, 0.7, 40.0}) {
    const double h = 1e-7 * std::max(std::abs(s), a);
    const ArctanPotential p = arctan_potential(s, a), pp = arctan_potential(s + h, a), pm = arctan_potential(s - h, a);
    EXPECT_NEAR(p.dpsi, (pp.psi - pm.psi) / (2 * h), 1e-6 * std::max(1.0, std::abs(p.dpsi))) << s;
    EXPECT_NEAR(p.d2psi, (pp.dpsi - pm.dpsi) / (2 * h), 1e-5 * p.d2psi) << s;
  }
  // Limits: the friction stress tends to tau_max as |s| >> a, and psi to |s|.
  EXPECT_NEAR(arctan_potential(1e3, 1e-3).dpsi, 1.0, 1e-6);
  EXPECT_NEAR(arctan_potential(-1e3, 1e-3).dpsi, -1.0, 1e-6);
  EXPECT_NEAR(arctan_potential(1e3, 1e-3).psi / 1e3, 1.0, 1e-4);
  EXPECT_EQ(arctan_potential(0.0, 1e-3).psi, 0.0);
}

