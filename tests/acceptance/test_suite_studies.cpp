// `rpfem suite` runs the studies of CASES/studies (docs/sweeps.md), without
// Python (--no-report): each study's table in OUT/studies/NAME, the same
// table `rpfem sweep` writes; the suite's --set does not reach a study;
// --scene and --study select them; a study's grid run that stops is in its
// table and leaves the exit code 0, its reference run stopping gives 3.
// Tiny runs of the flat-die upsetting (4 x 4 elements, 0.2 mm): about 5 s.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/types.hpp"
#include "results.hpp"
#include "run_case.hpp"

namespace fs = std::filesystem;
using namespace rpfem;

namespace {

const char* kScene = "upsetting_dies_frictionless_axisym";

// A temporary cases folder: the flat-die upsetting, a scene without
// contact, and two studies on the first: "beta" (penalty, Newton's force
// tolerance 1e-30 or 1e-7, against direct with reference_set) and "mesh".
std::string make_cases(const std::string& root, const std::string& reference_set) {
  const std::string cases = root + "/cases";
  fs::create_directories(cases + "/studies");
  for (const std::string s : {kScene, "upsetting_frictionless_axisym"})
    fs::copy_file(std::string(RPFEM_SOURCE_DIR) + "/cases/" + s + ".toml", cases + "/" + s + ".toml");
  std::ofstream(cases + "/studies/beta.toml") << R"([study]
case = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.2", "run.mesh_factor=0.2"]
[[study.axis]]
key = "solver.tol_force"
values = [1e-30, 1e-7]
[study.reference]
kind = "formulation"
formulation = "direct"
set = [)" << reference_set << R"(]
)";
  std::ofstream(cases + "/studies/mesh.toml") << R"([study]
case = "upsetting_dies_frictionless_axisym"
formulation = "direct"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.2"]
[[study.axis]]
key = "run.mesh_factor"
values = [0.1, 0.2, 0.4]
quick = [0.1, 0.2]
[study.reference]
kind = "richardson"
axis = "run.mesh_factor"
)";
  return cases;
}

struct Result {
  int rc = -1;
  std::string output;
};

Result run_rpfem(const std::string& args, const std::string& log) {
  Result r;
  r.rc = accept::rpfem(args, log, &r.output);
  return r;
}

std::string text(const std::string& path) { return read_text(path); }

// A numeric column of a study's table (its sweep.h5).
std::vector<double> column(const std::string& study_dir, const std::string& name) {
  return read_h5_dataset(study_dir + "/sweep.h5", "/table/" + name);
}

const std::string kSceneRuns = " --no-report --jobs 2 --set stepping.end_stroke=0.1 --set run.mesh_factor=0.2";

}  // namespace

TEST(SuiteStudies, EachStudysTableAsSweepWritesItStopsRecorded) {
  const std::string root = accept::test_out_dir();
  const std::string cases = make_cases(root, "");
  const Result r = run_rpfem("suite --cases " + cases + " --out " + root + "/o" + kSceneRuns, root + "/suite.log");
  // The beta study's run asking Newton for a residual of 1e-30 stops: its
  // table records it, the exit code stays 0.
  EXPECT_EQ(r.rc, 0) << r.output;
  const std::string beta = root + "/o/studies/beta";
  EXPECT_EQ(column(beta, "finished"), (std::vector<double>{0.0, 1.0}));
  // The suite's --set (end stroke 0.1 mm) does not reach a study (0.2 mm).
  ASSERT_EQ(column(beta, "final_stroke_mm").size(), 2u);
  EXPECT_NEAR(column(beta, "final_stroke_mm")[1], 0.2, 1e-9);
  // The same rows as `rpfem sweep` gives for the study.
  const Result sw = run_rpfem("sweep " + cases + "/studies/mesh.toml --cases " + cases + " --out " + root +
                              "/sweep --jobs 2 --quiet", root + "/sweep.log");
  EXPECT_EQ(sw.rc, 0) << sw.output;
  for (const char* c : {"final_load_kN", "load_error_final", "steps"}) {
    const auto in_suite = column(root + "/o/studies/mesh", c), own = column(root + "/sweep", c);
    EXPECT_EQ(in_suite.size(), 3u) << c;
    EXPECT_EQ(in_suite, own) << c;
  }
  // The manifest lists each study and where its tables are.
  const std::string manifest = text(root + "/o/suite.json");
  EXPECT_NE(manifest.find("\"table\" : \"studies/beta/sweep.csv\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"table\" : \"studies/mesh/sweep.csv\""), std::string::npos);
  EXPECT_NE(manifest.find("\"stopped\" : 1"), std::string::npos);
  EXPECT_NE(r.output.find("studies: 1 run stopped early"), std::string::npos) << r.output;
}

TEST(SuiteStudies, AStudysReferenceRunStoppingIsExitThree) {
  const std::string root = accept::test_out_dir();
  const std::string cases = make_cases(root, "\"solver.tol_force=1e-30\"");
  const Result r =
      run_rpfem("suite --cases " + cases + " --out " + root + "/o --study beta" + kSceneRuns, root + "/suite.log");
  EXPECT_EQ(r.rc, 3) << r.output;
  EXPECT_TRUE(fs::exists(root + "/o/studies/beta/sweep.csv"));
  EXPECT_FALSE(fs::exists(root + "/o/studies/mesh"));
  EXPECT_NE(text(root + "/o/suite.json").find("\"reference_exit_code\" : 3"), std::string::npos);
}

TEST(SuiteStudies, SceneAndStudySelection) {
  const std::string root = accept::test_out_dir();
  const std::string cases = make_cases(root, "");
  // --scene: only the studies on the scenes named, the others named as left out.
  Result r = run_rpfem("suite --cases " + cases + " --out " + root + "/a --scene upsetting_frictionless_axisym" +
                       kSceneRuns,
                   root + "/a.log");
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_FALSE(fs::exists(root + "/a/studies"));
  EXPECT_NE(r.output.find("studies left out, their scenes not selected by --scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("beta (upsetting_dies_frictionless_axisym)"), std::string::npos);
  // --study runs the study named whatever the scenes; --quick its reduced grid.
  r = run_rpfem("suite --cases " + cases + " --out " + root + "/b --scene upsetting_frictionless_axisym --study mesh "
            "--quick" + kSceneRuns,
            root + "/b.log");
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_EQ(column(root + "/b/studies/mesh", "run").size(), 2u);
  EXPECT_FALSE(fs::exists(root + "/b/studies/beta"));
  // --no-studies: none; an unknown study is bad input naming it.
  r = run_rpfem("suite --cases " + cases + " --out " + root + "/c --no-studies" + kSceneRuns, root + "/c.log");
  EXPECT_EQ(r.rc, 0) << r.output;
  EXPECT_FALSE(fs::exists(root + "/c/studies"));
  EXPECT_NE(text(root + "/c/suite.json").find("\"studies\" : []"), std::string::npos);
  r = run_rpfem("suite --cases " + cases + " --out " + root + "/d --study nosuch" + kSceneRuns, root + "/d.log");
  EXPECT_EQ(r.rc, 2);
  EXPECT_NE(r.output.find("no study 'nosuch'"), std::string::npos) << r.output;
}
