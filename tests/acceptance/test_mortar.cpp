// The mortar discretization (formulations/mortar) on the contact patch test
// (cases/patch_two_blocks.toml: two stacked blocks, non-matching meshes,
// 10 against 7 edges at the interface, frictionless platens): under every
// enforcement, with consistent or lumped slave weights and either block as
// the slave the strain rate and the contact pressure are uniform at every
// step. The uniform rate itself is
// off the incompressible v / H by the volumetric penalty's compressibility,
// 1.1e-6 to 1.4e-6 here as in one block without contact
// (upsetting_frictionless_axisym); the penalty's compliance adds 1e-5 at
// the first, instantaneous solve (nothing has yet built the gap that
// carries the pressure).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "field_comparison.hpp"
#include "homogeneous_flow.hpp"
#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

TEST(Mortar, PatchTestUnderEveryEnforcementWithEitherSlave) {
  for (const std::string weights : {"consistent", "lumped", "dual"})
    for (const std::string enf : {"penalty", "auglag", "ipopt"})
      for (const std::string slave : {"body", "with"}) {
        const std::string label =
            enf + ", " + weights + ", slave " + (slave == "body" ? "lower (10 edges)" : "upper (7 edges)");
        const std::string dir = run_case("patch_two_blocks",
                                         "--formulation " + enf + " --discretization mortar --set contact.slave=" +
                                             slave + " --set contact.slave_weights=" + weights,
                                         0, "_" + enf + "_" + slave + "_" + weights);
        const std::string h5 = dir + "/result.h5";
        const std::vector<int> steps = read_h5_steps(h5);
        ASSERT_EQ(steps.size(), 11u) << label;
        double rate = 0, exact = 0, spread = 0;
        for (int k : steps) {
          const HomogeneousFlowError e = homogeneous_flow_error(h5, k, 1.0, Geometry::Axisymmetric);
          if (k > 0 || enf != "penalty") exact = std::max(exact, e.strain_rate);
          char g[64];
          std::snprintf(g, sizeof g, "/steps/%06d/", k);
          const auto r = read_h5_dataset(h5, std::string(g) + "strain_rate");
          const auto [rlo, rhi] = std::minmax_element(r.begin(), r.end());
          rate = std::max(rate, (*rhi - *rlo) / *rhi);
          const auto p = read_h5_dataset(h5, std::string(g) + "node/contact_pressure");
          double lo = INFINITY, hi = 0;
          for (double q : p)
            if (q > 0) lo = std::min(lo, q), hi = std::max(hi, q);
          ASSERT_GT(hi, 0) << label << ", step " << k;
          spread = std::max(spread, (hi - lo) / hi);
        }
        EXPECT_LT(rate, 1e-6) << label;
        EXPECT_LT(spread, 1e-6) << label;
        EXPECT_LT(exact, 2e-6) << label;
        const History h = read_history(dir + "/history.csv");
        double imbalance = 0;
        for (std::size_t i = 0; i < h.rows(); ++i) imbalance = std::max(imbalance, h.at("force_imbalance")[i]);
        EXPECT_LT(imbalance, 1e-9) << label;
        std::printf("[measured] mortar patch test, %s: strain rate uniform to %.2e (off v / H by %.2e), contact "
                    "pressure to %.2e, action-reaction %.2e\n",
                    label.c_str(), rate, exact, spread, imbalance);
      }
}

// Mortar rows against a rigid die (contact.dies = "mortar"): upsetting
// between frictionless flat dies (cases/upsetting_dies_frictionless_axisym
// .toml, 50 %) keeps the top face on the die, so the rows weighted over the
// face must give the node rows' load at every step, the billet's corner
// (its normal tilted by the side) included. `direct` cannot hold such rows
// and says so.
TEST(Mortar, RowsAgainstARigidDieGiveTheNodeRowsLoad) {
  const std::string node = run_case("upsetting_dies_frictionless_axisym", "--formulation penalty", 0, "_node");
  const std::string mortar = run_case("upsetting_dies_frictionless_axisym",
                                      "--formulation penalty --discretization mortar --set contact.dies=mortar", 0,
                                      "_mortar");
  const History hn = read_history(node + "/history.csv"), hm = read_history(mortar + "/history.csv");
  ASSERT_EQ(hn.rows(), hm.rows());
  double worst = 0;
  for (std::size_t i = 0; i < hn.rows(); ++i) {
    ASSERT_NEAR(hm.at("stroke")[i], hn.at("stroke")[i], 1e-12);
    worst = std::max(worst, std::abs(hm.at("top_die.Fy")[i] / hn.at("top_die.Fy")[i] - 1));
  }
  EXPECT_LT(worst, 1e-6);
  std::printf("[measured] upsetting, mortar rows on the die against node rows: load %.2e\n", worst);
  std::string out;
  const std::string log = accept::test_out_dir("_direct") + ".log";
  EXPECT_EQ(accept::rpfem("run " + std::string(RPFEM_SOURCE_DIR) +
                              "/cases/upsetting_dies_frictionless_axisym.toml --quiet --discretization mortar --set "
                              "contact.dies=mortar --out " + accept::test_out_dir("_direct"),
                          log, &out),
            2);
  EXPECT_NE(out.find("contact.dies"), std::string::npos) << out;
}

// Test I's double action (cases/paper_test1_double_action.toml) under
// mortar with two half passes (variant mortar_both) to 1 mm: the
// discretization is mirror-symmetric, so the spheres' fields mirror each
// other at every recorded step although the split of the stroke between
// them is a stiff mode (one pass tips it: relative L2 differences of 2e-2
// to 7.7 in the strain rate over the stroke, docs/notes.md).
TEST(Mortar, TwoHalfPassesKeepTestIMirrored) {
  const std::string dir = run_case("paper_test1_double_action",
                                   "--variant mortar_both --set stepping.end_stroke=1.0 --set stepping.output_every=25");
  const std::string h5 = dir + "/result.h5";
  const std::vector<int> steps = read_h5_steps(h5);
  ASSERT_GE(steps.size(), 5u);
  const auto upper = [](const Vec2& p) { return p(1) > 0; };
  double rate = 0, vel = 0;
  for (int k : steps) {
    if (k == 0) continue;
    const FieldDifference m = field_difference(h5, h5, k, upper, PointMap::MirrorY);
    EXPECT_EQ(m.elements, 384);
    rate = std::max(rate, m.strain_rate), vel = std::max(vel, m.velocity);
  }
  // The penalty's mirror tolerance (PaperTest1 in test_penalty.cpp);
  // measured 9e-6 (Newton's tolerance, amplified by the stiff mode).
  EXPECT_LT(rate, 1e-3);
  EXPECT_LT(vel, 1e-3);
  const History h = read_history(dir + "/history.csv");
  EXPECT_NEAR(h.at("stroke").back(), 1.0, 1e-9);
  double pen = 0;
  for (std::size_t i = 0; i < h.rows(); ++i) pen = std::max(pen, h.at("max_penetration_rel")[i]);
  EXPECT_LT(pen, 1e-3);
  std::printf("[measured] Test I to 1 mm, mortar in two half passes: mirror L2 strain rate %.2e, velocity %.2e; "
              "rows' penetration / element size %.2e\n",
              rate, vel, pen);
}
