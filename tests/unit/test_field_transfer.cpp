// Moving a Gauss-point field to a new mesh (mesh/field_transfer.hpp):
// linear fields exactly, constants to round-off, from a structured mesh of
// a deformed billet to gmsh's mesh of its outline.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "fem/quad4.hpp"
#include "mesh/field_transfer.hpp"
#include "mesh/generate.hpp"
#include "mesh/outline_mesher.hpp"

using namespace rpfem;

namespace {

struct Meshes {
  Mesh old_mesh;
  std::vector<Vec2> old_x;
  OutlineMesh fresh;
};

// The barrelled billet of the outline mesher's test and its new mesh.
Meshes barrelled() {
  Meshes m;
  m.old_mesh = make_rectangle("billet", {0, 0, 10, 5, 10, 5});
  m.old_x = m.old_mesh.x;
  for (Vec2& p : m.old_x) {
    p(0) *= 1 + 0.1 * std::sin(kPi * p(1) / 5);
    p(1) -= 0.3 * (p(1) / 5) * (1 - p(0) / 12);
  }
  m.fresh = mesh_outline(m.old_mesh, m.old_x, 0, {0.6});
  return m;
}

Vec2 gauss_point(const Mesh& m, const std::vector<Vec2>& x, Index e, int q) {
  const Eigen::Vector4d N = quad4_shape(kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
  Vec2 p = Vec2::Zero();
  for (int i = 0; i < 4; ++i) p += N(i) * x[m.quads[e][i]];
  return p;
}

std::vector<GaussValues> sample(const Mesh& m, const std::vector<Vec2>& x, double (*f)(const Vec2&)) {
  std::vector<GaussValues> g(m.quads.size());
  for (Index e = 0; e < m.num_elements(); ++e)
    for (int q = 0; q < 4; ++q) g[e][q] = f(gauss_point(m, x, e, q));
  return g;
}

double linear(const Vec2& p) { return 0.3 + 0.05 * p(0) - 0.02 * p(1); }
double constant(const Vec2&) { return 0.7; }
double quadratic(const Vec2& p) { return 0.01 * p(0) * p(0) + 0.02 * p(1) * p(1); }

}  // namespace

TEST(FieldTransfer, LinearFieldsExactlyConstantsToRoundOff) {
  const Meshes m = barrelled();
  const Mesh& fresh = m.fresh.mesh;
  for (auto* f : {&linear, &constant}) {
    const auto moved = transfer_gauss_field(m.old_mesh, m.old_x, sample(m.old_mesh, m.old_x, f), fresh, fresh.x);
    double worst = 0;
    for (Index e = 0; e < fresh.num_elements(); ++e)
      for (int q = 0; q < 4; ++q)
        worst = std::max(worst, std::abs(moved[e][q] - f(gauss_point(fresh, fresh.x, e, q))));
    EXPECT_LT(worst, 1e-13) << (f == &linear ? "linear" : "constant");
  }
  // Recovery at the nodes alone: a linear field at every old node.
  const auto nodal = recover_at_nodes(m.old_mesh, m.old_x, sample(m.old_mesh, m.old_x, &linear));
  for (std::size_t n = 0; n < nodal.size(); ++n) EXPECT_NEAR(nodal[n], linear(m.old_x[n]), 1e-13) << n;
}

TEST(FieldTransfer, ASmoothFieldToTheRecoverysOrder) {
  // A quadratic field is not reproduced: inside, the error is the bilinear
  // interpolation's, f'' h^2 / 8; at the outline the patch's plane is
  // extrapolated half an element, up to f'' h^2 / 2 (largest f'' = 0.04,
  // old elements up to h = 1.1 mm: 0.024; measured 0.0185).
  const Meshes m = barrelled();
  const Mesh& fresh = m.fresh.mesh;
  const auto moved =
      transfer_gauss_field(m.old_mesh, m.old_x, sample(m.old_mesh, m.old_x, &quadratic), fresh, fresh.x);
  double worst = 0;
  for (Index e = 0; e < fresh.num_elements(); ++e)
    for (int q = 0; q < 4; ++q)
      worst = std::max(worst, std::abs(moved[e][q] - quadratic(gauss_point(fresh, fresh.x, e, q))));
  std::printf("[measured] quadratic field moved: worst error %.2e\n", worst);
  EXPECT_GT(worst, 1e-6);  // not exact: the test would pass a wrong reference otherwise
  EXPECT_LT(worst, 0.5 * 0.04 * 1.1 * 1.1);
}
