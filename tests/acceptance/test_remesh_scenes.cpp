// The scenes that need remeshing (cases/*_remeshed.toml and
// backward_extrusion_cup.toml) run to their end under the direct
// formulation: every step's least scaled Jacobian at least 0.2, each
// remesh's volume change below 1e-6 and, where stated, its own load jump
// (the new mesh's load at the remesh's configuration against the old
// one's) below 1 %; the ring's load and inner diameter do not depend on
// when it is remeshed. The other enforcements on the same scenes:
// docs/decisions.md, "Remeshing" (a study, too long for a test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

namespace {

// Every value of `key` in summary.json's remeshes (e.g. "load_jump").
std::vector<double> remesh_values(const std::string& dir, const std::string& key) {
  const std::string s = read_text(dir + "/summary.json");
  std::vector<double> v;
  const std::string quoted = "\"" + key + "\"";
  for (std::size_t p = 0; (p = s.find(quoted, p)) != std::string::npos; ++p)
    v.push_back(std::strtod(s.c_str() + s.find(':', p) + 1, nullptr));
  return v;
}

double largest_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// The checks every remeshed scene must pass; returns its history.
//~ helper = "check_remeshed_run"
//~ [[check]]
//~ what = "the run finishes at its end stroke; at least 3 remeshes"
//~ compares = "expected behaviour"
//~ tolerance = "1e-9 mm; >= 3 remeshes"
//~ why = "a scene that needs remeshing must get through it, and must have needed it"
//~ [[check]]
//~ what = "least scaled Jacobian at every step"
//~ compares = "expected behaviour"
//~ tolerance = ">= 0.2"
//~ why = "remeshing must keep the elements usable; below 0.2 the elements near a corner are too distorted to trust"
//~ [[check]]
//~ what = "each remesh's volume change"
//~ compares = "conservation"
//~ tolerance = "1e-6"
//~ why = "the mesher keeps the outline: measured below 4e-15"
//~ [[check]]
//~ what = "each remesh's load jump, where the scene states it"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-2 (relative)"
//~ why = "the new mesh's load at the same configuration is another discretization of a non-homogeneous field; 1 % bounds that and fails on a lost contact state or a wrong field transfer"
History check_remeshed_run(const std::string& dir, double end_stroke, bool jumps_below_1_percent) {
  EXPECT_TRUE(run_finished(dir)) << dir;
  const History h = read_history(dir + "/history.csv");
  EXPECT_NEAR(h.at("stroke").back(), end_stroke, 1e-9) << dir;
  const auto& q = h.at("min_scaled_jacobian");
  EXPECT_GE(*std::min_element(q.begin(), q.end()), 0.2) << dir;
  const auto volume = remesh_values(dir, "volume_change");
  const auto jump = remesh_values(dir, "load_jump");
  EXPECT_GE(volume.size(), 3u) << dir << ": it needs remeshing";
  EXPECT_EQ(jump.size(), volume.size()) << dir;
  EXPECT_LT(largest_abs(volume), 1e-6) << dir;
  if (jumps_below_1_percent) EXPECT_LT(largest_abs(jump), 1e-2) << dir;
  // summary.json's keys in order: final_mesh, mesh, the remeshes: the
  // final mesh is the last remesh's.
  const auto elements = remesh_values(dir, "elements");
  EXPECT_GE(elements.size(), 3u) << dir;
  if (!elements.empty()) EXPECT_EQ(elements.front(), elements.back()) << dir << ": final_mesh";
  std::printf("[measured] %s: %zu remeshes, largest volume change %.2e, largest load jump %.4f, least scaled "
              "Jacobian %.3f\n",
              dir.c_str(), volume.size(), largest_abs(volume), largest_abs(jump),
              *std::min_element(q.begin(), q.end()));
  return h;
}

}  // namespace

//~ feature = "remeshing"
//~ scene = "upsetting_sticking_remeshed (direct) to 70 %"
//~ source = "the remesher keeps the outline (volume) and the state (load)"
//~ uses = ["check_remeshed_run"]
TEST(RemeshScenes, UpsettingWithStickingFrictionTo70Percent) {
  const std::string dir = run_case("upsetting_sticking_remeshed");
  check_remeshed_run(dir, 7.0, true);
}

//~ feature = "remeshing"
//~ scene = "ring_compression_remeshed, variants m1, mu0.2, m1_q0.5, m1_every0.5mm, to 60 %"
//~ source = "Male and Cockcroft 1964 (the ring's inner diameter)"
//~ uses = ["check_remeshed_run"]
//~ [[check]]
//~ what = "m = 1 remeshed at another criterion: load at 60 % against the default criteria's"
//~ compares = "the same scene run otherwise"
//~ tolerance = "1e-2 (relative)"
//~ why = "when a remesh happens must not change the result beyond the discretization's spread"
//~ [[check]]
//~ what = "inner-diameter change at every step against the default criteria's curve"
//~ compares = "the same scene run otherwise"
//~ tolerance = "0.5 percentage points"
//~ why = "the spread of the remeshed discretization on this mesh is 0.4 to 0.5 point (runs under two BLAS differ by up to 0.33 point: gmsh meshes an outline differing at round-off differently)"
TEST(RemeshScenes, RingTo60PercentWhicheverTheCriteria) {
  const std::string dir = run_case("ring_compression_remeshed", "--variant all");
  for (const std::string v : {"m1", "mu0.2", "m1_q0.5", "m1_every0.5mm"}) check_remeshed_run(dir + "/" + v, 6.0, true);
  // m = 1 remeshed at a least scaled Jacobian of 0.3, of 0.5, and every
  // 0.5 mm besides: the load at 60 % within 1 %, the inner diameter
  // within 0.5 point at every step (each run's steps against the first's
  // curve).
  const History ref = read_history(dir + "/m1/history.csv");
  for (const std::string v : {"m1_q0.5", "m1_every0.5mm"}) {
    const History h = read_history(dir + "/" + v + "/history.csv");
    const double end = std::abs(h.at("top_die.Fy").back() / ref.at("top_die.Fy").back() - 1);
    EXPECT_LT(end, 1e-2) << v;
    double id = 0;
    const auto& s = h.at("stroke");
    for (std::size_t i = 0; i < s.size(); ++i) {
      const auto& rs = ref.at("stroke");
      const std::size_t j = std::min<std::size_t>(std::upper_bound(rs.begin(), rs.end(), s[i]) - rs.begin(), rs.size() - 1);
      const std::size_t k = j > 0 ? j - 1 : 0;
      const double t = rs[j] > rs[k] ? (s[i] - rs[k]) / (rs[j] - rs[k]) : 0.0;
      const auto& d = ref.at("inner_diameter_mid");
      id = std::max(id, std::abs(h.at("inner_diameter_mid")[i] - (d[k] + t * (d[j] - d[k]))));
    }
    EXPECT_LT(id, 0.5) << v;
    const double curve = load_difference(h, "top_die.Fy", ref, "top_die.Fy", 0.5, 0.05);
    std::printf("[measured] ring m = 1, %s against the default criteria: load at 60 %% %.4f apart (over the "
                "stroke from 0.5 mm, a step's shift allowed: %.4f), inner diameter %.3f point\n",
                v.c_str(), end, curve, id);
  }
}

//~ feature = "remeshing"
//~ scene = "backward_extrusion_cup (direct) to 8 mm"
//~ source = "volume constancy: the rim rises (7/10)^2 / (1 - (7/10)^2) = 0.96 mm per mm of punch travel once the flow is steady"
//~ uses = ["check_remeshed_run"]
//~ [[check]]
//~ what = "rim rise per mm of travel from 4 to 8 mm; cup bottom thickness at 8 mm"
//~ compares = "exact solution"
//~ tolerance = "0.02 (mm per mm; mm)"
//~ why = "the steady flow's volume balance; 0.02 is 2 % of the rise, read at the nearest recorded strokes"
//~ [[check]]
//~ what = "every remesh restored the overlap with the punch's corner"
//~ compares = "expected behaviour"
//~ tolerance = "> 0.0"
//~ why = "the new outline cuts the corner; the volume inside the punch is put back"
TEST(RemeshScenes, BackwardExtrusionOfACup) {
  const std::string dir = run_case("backward_extrusion_cup");
  const History h = check_remeshed_run(dir, 8.0, true);
  // Volume constancy: once the flow is steady the rim rises (7/10)^2 /
  // (1 - (7/10)^2) = 0.96 mm per mm of punch travel, and the cup's bottom
  // is the slug's height less the travel.
  const auto& s = h.at("stroke");
  const auto at = [&](const std::string& col, double stroke) {
    const std::size_t i = std::min_element(s.begin(), s.end(), [&](double a, double b) {
                            return std::abs(a - stroke) < std::abs(b - stroke);
                          }) - s.begin();
    return h.at(col)[i];
  };
  EXPECT_NEAR((at("cup_rim_height", 8.0) - at("cup_rim_height", 4.0)) / 4.0, 0.49 / 0.51, 0.02);
  EXPECT_NEAR(at("cup_bottom_thickness", 8.0), 4.0, 0.02);
  // Every remesh put the overlap with the punch's corner back.
  EXPECT_GT(largest_abs(remesh_values(dir, "volume_restored")), 0.0);
}
