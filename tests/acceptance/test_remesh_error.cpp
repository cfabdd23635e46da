// Meshes from the error (remesh.target_error, model/error_size_field.hpp):
// the backward extrusion (cases/backward_extrusion_cup.toml, direct) to
// 2 mm, remeshed every 0.5 mm, without the dies' corners' grading
// (die_corner_size = 1) so that whatever grading the new meshes have comes
// from the error. Against the same run remeshed uniformly: the
// indicator's largest element lies at the punch's edge fillet in both; the
// sized meshes are finer there, the uniform ones are not; the estimate on
// the new mesh at each remesh meets the target; over the stroke the sized
// run's estimate is well below the uniform run's at a similar count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

namespace {

// summary.json's remeshes, each as its numbers by key.
std::vector<std::map<std::string, double>> remesh_entries(const std::string& dir) {
  const std::string s = read_text(dir + "/summary.json");
  std::vector<std::map<std::string, double>> out;
  std::size_t p = s.find("\"remeshes\"");
  if (p == std::string::npos) return out;
  // The list's closing bracket (an entry may hold a list of names).
  std::size_t end = s.find('[', p);
  for (int depth = 0; end < s.size(); ++end) {
    if (s[end] == '[') ++depth;
    if (s[end] == ']' && --depth == 0) break;
  }
  for (p = s.find('{', p); p < end; p = s.find('{', p + 1)) {
    const std::size_t close = s.find('}', p);
    auto& entry = out.emplace_back();
    for (std::size_t q = s.find('"', p); q < close;) {
      const std::size_t r = s.find('"', q + 1);
      const std::size_t v = s.find_first_not_of(" :", r + 1);
      if (s[v] == '"') {  // a text (the reason): skipped
        q = s.find('"', s.find('"', v + 1) + 1);
        continue;
      }
      if (s[v] == '[') {  // a list of names (subdivided): skipped
        q = s.find('"', s.find(']', v) + 1);
        continue;
      }
      entry[s.substr(q + 1, r - q - 1)] = std::strtod(s.c_str() + v, nullptr);
      q = s.find('"', v);
    }
  }
  return out;
}

// Element centres and sizes (sqrt of the area) of a mesh in result.h5.
struct Elements {
  std::vector<Vec2> centre;
  std::vector<double> size;
};
Elements elements(const std::string& h5, const std::string& mesh, const std::string& coordinates) {
  std::vector<unsigned long long> shape;
  const auto conn = read_h5_dataset(h5, mesh + "/connectivity", &shape);
  const auto x = read_h5_dataset(h5, coordinates);
  Elements out;
  for (std::size_t e = 0; e < shape[0]; ++e) {
    Vec2 c = Vec2::Zero();
    double a = 0;
    for (int i = 0; i < 4; ++i) {
      const auto p = static_cast<std::size_t>(conn[4 * e + i]), q = static_cast<std::size_t>(conn[4 * e + (i + 1) % 4]);
      c += 0.25 * Vec2(x[2 * p], x[2 * p + 1]);
      a += 0.5 * (x[2 * p] * x[2 * q + 1] - x[2 * q] * x[2 * p + 1]);
    }
    out.centre.push_back(c), out.size.push_back(std::sqrt(std::abs(a)));
  }
  return out;
}

struct RemeshLook {
  double worst_from_fillet = 0;  // mm, the old mesh's largest indicator from the fillet's middle
  double near_over_median = 0;   // new mesh: mean size within 1 mm of it over the median size
};

// At the remesh at `step` (stroke s): the old mesh's element of the largest
// eta_e^2 ~ rms^2 A r (axisymmetric), and the new mesh's sizes around it.
RemeshLook look(const std::string& h5, int step, double s) {
  char group[32];
  std::snprintf(group, sizeof group, "/steps/%06d", step);
  const std::string old_mesh = read_h5_text_attribute(h5, group, "mesh");
  const Elements old = elements(h5, old_mesh, std::string(group) + "/coordinates");
  const auto rms = read_h5_dataset(h5, std::string(group) + "/element/strain_rate_error");
  std::size_t worst = 0;
  const auto eta2 = [&](std::size_t e) { return rms[e] * rms[e] * old.size[e] * old.size[e] * old.centre[e](0); };
  for (std::size_t e = 0; e < rms.size(); ++e)
    if (eta2(e) > eta2(worst)) worst = e;
  // The punch's edge fillet (radius 1 mm about (6, 13) at the start) at
  // 45 degrees.
  const Vec2 fillet(6 + std::sqrt(0.5), 13 - s - std::sqrt(0.5));
  char mesh[32];
  std::snprintf(mesh, sizeof mesh, "/meshes/%06d", step + 1);
  const Elements fresh = elements(h5, mesh, std::string(mesh) + "/initial_coordinates");
  std::vector<double> sorted = fresh.size;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  double near = 0;
  int count = 0;
  for (std::size_t e = 0; e < fresh.size.size(); ++e)
    if ((fresh.centre[e] - old.centre[worst]).norm() < 1.0) near += fresh.size[e], ++count;
  return {(old.centre[worst] - fillet).norm(), near / std::max(count, 1) / sorted[sorted.size() / 2]};
}

// Over the stroke from 0.6 mm (after the first remesh): the mean of
// history.csv's strain_rate_error and of the element count.
std::pair<double, double> means(const std::string& dir, const std::vector<std::map<std::string, double>>& remeshes) {
  const History h = read_history(dir + "/history.csv");
  double error = 0, count = 0;
  int rows = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) {
    if (h.at("stroke")[i] < 0.6) continue;
    double elements = 480;  // the case's mesh
    for (const auto& r : remeshes)
      if (h.at("step")[i] > r.at("step")) elements = r.at("elements");
    error += h.at("strain_rate_error")[i], count += elements, ++rows;
  }
  return {error / rows, count / rows};
}

}  // namespace

//~ feature = "remeshing"
//~ scene = "backward_extrusion_cup (direct) to 2 mm, remeshed every 0.5 mm, die_corner_size = 1: remesh.target_error = 0.05 against the uniform remesh"
//~ source = "Zienkiewicz and Zhu 1987 (the estimate); Li and Bettess 1995 (the size rule)"
//~ [[check]]
//~ what = "at every remesh of both runs, the old mesh's element of the largest indicator from the middle of the punch's edge fillet"
//~ compares = "expected behaviour"
//~ tolerance = "< 1.0 mm"
//~ why = "the flow turns round the punch's edge: the strain rate's steepest gradients, where the sizes must fall (measured 0.14 to 0.77 mm)"
//~ [[check]]
//~ what = "new mesh's mean element size within 1 mm of that element over its median size: sized run, uniform run"
//~ compares = "the same scene run otherwise"
//~ tolerance = "< 0.6 sized; > 0.75 uniform"
//~ why = "the size from the error refines where the indicator is largest (measured 0.29 to 0.49); the uniform remesh (0.83 to 1.06) shows the check can fail"
//~ [[check]]
//~ what = "the relative estimate on the new mesh at the remesh's configuration (strain_rate_error_after) over the target"
//~ compares = "expected behaviour"
//~ tolerance = "< 1.5; the first remesh < 2.0"
//~ why = "measured 1.17 to 1.23, the first 1.66: the a-priori rule assumes the O(h) rate everywhere; the contact front converges slower. The first remesh keeps the case's coarse outline nodes across the punch's fillet (its outline is kept): a kink the size cannot remove"
//~ [[check]]
//~ what = "mean relative estimate and mean element count over the stroke from 0.6 mm, sized against uniform"
//~ compares = "the same scene run otherwise"
//~ tolerance = "error ratio < 0.6; count ratio < 1.4"
//~ why = "measured 0.43 and 1.16; the point of sizing by the error: far less error for about the elements; uniform needs 4787 elements (0.18 mm) for 0.069"
TEST(RemeshError, SizedByTheErrorFinerAtThePunchEdgeAndMeetsTheTarget) {
  const std::string common = "--set stepping.end_stroke=2.0 --set remesh.stroke_interval=0.5 "
                             "--set remesh.die_corner_size=1.0";
  const std::string sized = run_case("backward_extrusion_cup", common + " --set remesh.target_error=0.05", 0, "_sized");
  const std::string uniform = run_case("backward_extrusion_cup", common, 0, "_uniform");
  const double target = 0.05;
  for (const std::string& dir : {sized, uniform}) {
    EXPECT_TRUE(run_finished(dir)) << dir;
    const auto remeshes = remesh_entries(dir);
    ASSERT_GE(remeshes.size(), 3u) << dir;
    for (std::size_t k = 0; k < remeshes.size(); ++k) {
      const auto& r = remeshes[k];
      const RemeshLook l = look(dir + "/result.h5", static_cast<int>(r.at("step")), r.at("stroke_mm"));
      EXPECT_LT(l.worst_from_fillet, 1.0) << dir << " remesh " << k;
      if (dir == sized) {
        EXPECT_LT(l.near_over_median, 0.6) << "remesh " << k;
        EXPECT_LT(r.at("strain_rate_error_after") / target, k == 0 ? 2.0 : 1.5) << "remesh " << k;
      } else {
        EXPECT_GT(l.near_over_median, 0.75) << "remesh " << k;
      }
      std::printf("[measured] %s remesh at %.2f mm: %g elements, estimate %.4f before, %.4f after; largest indicator "
                  "%.2f mm from the fillet, new sizes there %.2f of the median\n",
                  dir == sized ? "sized" : "uniform", r.at("stroke_mm"), r.at("elements"),
                  r.at("strain_rate_error_before"), r.at("strain_rate_error_after"), l.worst_from_fillet,
                  l.near_over_median);
    }
  }
  const auto [error_sized, count_sized] = means(sized, remesh_entries(sized));
  const auto [error_uniform, count_uniform] = means(uniform, remesh_entries(uniform));
  EXPECT_LT(error_sized / error_uniform, 0.6);
  EXPECT_LT(count_sized / count_uniform, 1.4);
  std::printf("[measured] over the stroke from 0.6 mm: sized %.4f with %.0f elements, uniform %.4f with %.0f\n",
              error_sized, count_sized, error_uniform, count_uniform);
}

//~ feature = "remeshing"
//~ scene = "backward_extrusion_cup (direct) to 0.05 mm, remesh.initial_mesh = true, die_corner_size = 1: target_error = 0.05 against none"
//~ source = "Li and Bettess 1995 (the size rule), on the error of a first solve on the case's mesh"
//~ [[check]]
//~ what = "initial mesh: mean element size within 1 mm of the punch's edge (6.5, 12) over the median size, sized against uniform"
//~ compares = "the same scene run otherwise"
//~ tolerance = "< 0.6 sized; > 0.75 uniform"
//~ why = "step 0's largest errors lie where the punch's flat face ends (measured 0.31 sized); without a target the initial mesh is uniform"
TEST(RemeshError, InitialMeshSizedByTheFirstSolvesError) {
  const std::string common = "--set stepping.end_stroke=0.05 --set remesh.initial_mesh=true "
                             "--set remesh.die_corner_size=1.0";
  const std::string sized = run_case("backward_extrusion_cup", common + " --set remesh.target_error=0.05", 0, "_sized");
  const std::string uniform = run_case("backward_extrusion_cup", common, 0, "_uniform");
  for (const std::string& dir : {sized, uniform}) {
    EXPECT_TRUE(run_finished(dir)) << dir;
    const Elements m = elements(dir + "/result.h5", "/mesh", "/mesh/initial_coordinates");
    std::vector<double> sorted = m.size;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    double near = 0;
    int count = 0;
    for (std::size_t e = 0; e < m.size.size(); ++e)
      if ((m.centre[e] - Vec2(6.5, 12.0)).norm() < 1.0) near += m.size[e], ++count;
    const double ratio = near / std::max(count, 1) / sorted[sorted.size() / 2];
    if (dir == sized)
      EXPECT_LT(ratio, 0.6);
    else
      EXPECT_GT(ratio, 0.75);
    const History h = read_history(dir + "/history.csv");
    std::printf("[measured] initial mesh %s: %zu elements, sizes at the punch's edge %.2f of the median; step 0's "
                "estimate %.4f\n",
                dir == sized ? "sized" : "uniform", m.size.size(), ratio, h.at("strain_rate_error")[0]);
  }
}
