// `rpfem suite` runs the studies of CASES/studies (docs/sweeps.md), without
// Python (--no-report): each study's table in OUT/studies/NAME, the same
// table `rpfem sweep` writes; the suite's --set does not reach a study;
// --scene and --study select them; a study's grid run that stops is in its
// table and leaves the exit code 0, its reference run stopping gives 3; a
// regularization study's monitor errors, orders and reference run.
// Tiny runs of the flat-die upsetting (4 x 4 elements, 0.2 mm) and of the
// upsetting with friction (4 x 4, 1 mm): about 6 s.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
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

//~ feature = "studies"
//~ scene = "a temporary cases folder: flat-die upsetting, two studies (beta, mesh) on 4 x 4 meshes"
//~ source = "docs/sweeps.md (a study's table)"
//~ [[check]]
//~ what = "a study's run that stops is in its table, the exit code stays 0; the suite's --set does not reach a study"
//~ compares = "expected behaviour"
//~ tolerance = "exit 0; final stroke 1e-9 mm"
//~ why = "a study measures where runs stop; the study's own settings decide its runs"
//~ [[check]]
//~ what = "the study's table in the suite against `rpfem sweep`'s for the same study"
//~ compares = "the same scene run otherwise"
//~ tolerance = "equal"
//~ why = "the same runs give the same numbers"
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

//~ feature = "studies"
//~ scene = "the beta study with a reference run that cannot converge"
//~ source = "docs/sweeps.md (the reference run)"
//~ [[check]]
//~ what = "exit code 3; reference_exit_code 3 in suite.json"
//~ compares = "expected behaviour"
//~ tolerance = "exit 3"
//~ why = "a study without its reference cannot report errors: the suite says so"
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

//~ feature = "studies"
//~ scene = "the same cases folder, --scene, --study, --quick, --no-studies, an unknown study"
//~ source = "docs/sweeps.md (selecting studies)"
//~ [[check]]
//~ what = "only the studies selected run; --quick the reduced grid; an unknown study is bad input naming it"
//~ compares = "expected behaviour"
//~ tolerance = "exit 0 or 2"
//~ why = "selection is exact: what runs is what was asked for, and a typo is an error"
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

// The friction's smoothing a against the exact law (ssn) on the upsetting
// with Coulomb friction, 4 x 4 elements to 1 mm under direct: the load and
// the top corner's radius converge with order 1 as a falls (0.97 and 0.97
// from a = 0.1 to 1e-3), the reference run's own values are in sweep.json.
//~ feature = "studies"
//~ scene = "upsetting_friction, Coulomb mu = 0.1, 4 x 4 elements to 1 mm: direct at a = 0.1, 1e-2, 1e-3 against ssn"
//~ source = "paper eq. 11-12 (the arctan law's error is first order in a); Hueber, Stadler and Wohlmuth 2008 (the exact reference)"
//~ [[check]]
//~ what = "load and monitor errors falling by more than 5 per decade of a"
//~ compares = "another formulation"
//~ tolerance = "> 5 x per decade"
//~ why = "first order gives 10 per decade; 5 allows the coarse mesh's pre-asymptotic error"
//~ [[check]]
//~ what = "fitted orders in sweep.json (load and top corner radius)"
//~ compares = "another formulation"
//~ tolerance = "1.0 +- 0.1"
//~ why = "measured 0.97 and 0.97 from a = 0.1 to 1e-3"
TEST(SuiteStudies, ARegularizationStudysErrorsOrdersAndReference) {
  const std::string root = accept::test_out_dir();
  const std::string cases = root + "/cases";
  fs::create_directories(cases + "/studies");
  fs::copy_file(std::string(RPFEM_SOURCE_DIR) + "/cases/upsetting_friction.toml", cases + "/upsetting_friction.toml");
  std::ofstream(cases + "/studies/smoothing.toml") << R"([study]
case = "upsetting_friction"
load = "top_die.Fy"
monitor = "top_corner_radius"
set = ["dies.top_die.friction.law=coulomb", "dies.top_die.friction.mu=0.1", "stepping.end_stroke=1.0",
       "run.mesh_factor=0.2"]
[[study.axis]]
key = "formulation"
values = ["direct"]
[[study.axis]]
key = "dies.top_die.friction.a"
values = [1e-1, 1e-2, 1e-3]
[study.reference]
kind = "formulation"
formulation = "ssn"
[study.regularization]
axis = "dies.top_die.friction.a"
default = 1e-2
)";
  const Result r = run_rpfem("suite --cases " + cases + " --out " + root + "/o --scene upsetting_friction --no-variants"
                             " --study smoothing" + kSceneRuns, root + "/suite.log");
  ASSERT_EQ(r.rc, 0) << r.output;
  const std::string dir = root + "/o/studies/smoothing";
  // Errors against the reference run at every a, falling by about 10 per decade.
  for (const char* c : {"load_error_final", "mean_load_error", "monitor_error", "monitor_error_final"}) {
    const auto e = column(dir, c);
    ASSERT_EQ(e.size(), 3u) << c;
    EXPECT_GT(e[0], 5 * e[1]) << c;
    EXPECT_GT(e[1], 5 * e[2]) << c;
    EXPECT_GT(e[2], 0.0) << c;
  }
  // sweep.json: the load's and the monitor's fitted orders, the errors at
  // the default, the monitor's unit, the reference run's own values.
  const std::string meta = text(dir + "/sweep.json");
  const std::regex fit("\"fit_order\" : ([-0-9.eE+]+)");
  int orders = 0;
  for (auto m = std::sregex_iterator(meta.begin(), meta.end(), fit); m != std::sregex_iterator(); ++m, ++orders)
    EXPECT_NEAR(std::stod((*m)[1]), 1.0, 0.1) << meta;
  EXPECT_EQ(orders, 2) << meta;
  EXPECT_NE(meta.find("\"unit\" : \"mm\""), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"load_error\" : \"load_error_final\""), std::string::npos);
  const std::regex at_default("\"error_at_default\" : ([-0-9.eE+]+)");
  const auto loads = column(dir, "load_error_final"), radii = column(dir, "monitor_error_final");
  std::vector<double> at;
  for (auto m = std::sregex_iterator(meta.begin(), meta.end(), at_default); m != std::sregex_iterator(); ++m)
    at.push_back(std::stod((*m)[1]));
  ASSERT_EQ(at.size(), 2u) << meta;
  EXPECT_DOUBLE_EQ(at[0], loads[1]);  // a = 1e-2, the second value
  EXPECT_DOUBLE_EQ(at[1], radii[1]);
  const auto ref = meta.find("\"reference_run\"");
  ASSERT_NE(ref, std::string::npos) << meta;
  const std::string reference = meta.substr(ref, meta.find('}', ref) - ref);  // a flat table
  for (const char* k : {"\"formulation\" : \"ssn\"", "\"finished\" : 1.0", "\"iterations_median\"",
                        "\"wall_time_s\"", "\"monitor_final\""})
    EXPECT_NE(reference.find(k), std::string::npos) << k << " in " << reference;
}
