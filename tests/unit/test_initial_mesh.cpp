// remesh.initial_mesh (model/remesh.hpp): the backward extrusion's
// slug meshed by the remesher before the first step keeps its outline (the
// volume to round-off, every named side's end points) and is graded at the
// dies' corners as every remesh of the run is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "io/case_file.hpp"
#include "io/scene_reader.hpp"
#include "model/remesh.hpp"

using namespace rpfem;

namespace {

// int 2 pi r dA over the mesh (Green's theorem per element).
double axisymmetric_volume(const Mesh& m) {
  double v = 0;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) {
      const Vec2 &p = m.x[q[k]], &n = m.x[q[(k + 1) % 4]];
      v += 2 * kPi * (p(0) + n(0)) * cross(p, n) / 6;
    }
  return v;
}

// The shortest and the mean edge of the elements with a node within r of c.
std::pair<double, double> edges_near(const Mesh& m, const Vec2& c, double r) {
  double shortest = std::numeric_limits<double>::infinity(), sum = 0;
  int count = 0;
  for (const auto& q : m.quads) {
    if (std::none_of(q.begin(), q.end(), [&](Index n) { return (m.x[n] - c).norm() < r; })) continue;
    for (int k = 0; k < 4; ++k) {
      const double l = (m.x[q[(k + 1) % 4]] - m.x[q[k]]).norm();
      shortest = std::min(shortest, l), sum += l, ++count;
    }
  }
  return {shortest, count ? sum / count : 0.0};
}

}  // namespace

TEST(InitialMesh, KeepsTheOutlineAndItsSidesAndIsGradedAtTheDiesCorners) {
  CaseFile file(std::string(RPFEM_SOURCE_DIR) + "/cases/backward_extrusion_cup.toml", {"remesh.initial_mesh=true"});
  const Scene scene = read_scene(file);
  ASSERT_TRUE(scene.remesh.initial_mesh);
  const Scene meshed = initial_remesh(scene);
  const Mesh &a = scene.mesh, &b = meshed.mesh;
  ASSERT_NE(a.num_elements(), b.num_elements());
  const double volume = std::abs(axisymmetric_volume(b) / axisymmetric_volume(a) - 1);
  EXPECT_LT(volume, 1e-12);
  // Every named side is there, with the same end points (the corners).
  for (const auto& [name, edges] : a.sides) {
    ASSERT_TRUE(b.sides.count(name)) << name;
    if (name.find(".boundary") != std::string::npos) continue;
    const auto ends = [](const Mesh& m, const std::vector<Edge>& side) {
      Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
      for (const Edge& e : side)
        for (Index n : {e.a, e.b}) lo = lo.cwiseMin(m.x[n]), hi = hi.cwiseMax(m.x[n]);
      return std::make_pair(lo, hi);
    };
    const auto [lo_a, hi_a] = ends(a, edges);
    const auto [lo_b, hi_b] = ends(b, b.sides.at(name));
    EXPECT_EQ(lo_a, lo_b) << name;
    EXPECT_EQ(hi_a, hi_b) << name;
  }
  // The case's mesh is uniform, 0.5 mm; at the punch's edge fillet (its
  // corner at x = 7 on the slug's top, y = 12) the size falls to 0.25 of
  // it, away from every die's corner it stays.
  const auto [corner_short, corner_mean] = edges_near(b, Vec2(7.0, 12.0), 0.5);
  const auto [far_short, far_mean] = edges_near(b, Vec2(0.0, 6.0), 1.0);
  EXPECT_LT(corner_short, 0.2);
  EXPECT_GT(far_mean, 0.4);
  std::printf("[measured] initial mesh: %lld elements (the case's %lld), volume %.2e; edges at the punch corner from "
              "%.3f mm (mean %.3f), at the axis mid-height mean %.3f\n",
              (long long)b.num_elements(), (long long)a.num_elements(), volume, corner_short, corner_mean, far_mean);
}
