// Requirement (kernel): the element loops' threads change nothing. Coulomb
// upsetting on a 40 x 40 mesh (1600 elements, above the loops' serial
// threshold) with one and with two threads: history.csv and every field of
// result.h5 the same bits (model/element_loop.hpp: each element's terms
// in its own slot, the sums in element order).
#include <gtest/gtest.h>

#include <string>

#include "results.hpp"
#include "run_case.hpp"

using namespace rpfem;
using accept::run_case;

//~ feature = "threads"
//~ scene = "upsetting_friction, direct, mesh factor 2 (1600 elements) to 1 mm, one and two threads"
//~ source = "model/element_loop.hpp: each element's terms in its own slot, the sums in element order"
//~ [[check]]
//~ what = "history.csv and the last step's velocity, strain and coordinates (h5dump, 17 digits)"
//~ compares = "the same scene run otherwise"
//~ tolerance = "equal bits"
//~ why = "the sums are taken in the same order whatever the thread count"
TEST(Threads, ElementLoopsGiveTheSameBitsOnOneAndTwoThreads) {
  const std::string common =
      "--formulation direct --set run.mesh_factor=2 --set stepping.end_stroke=1.0 --set solver.threads=";
  const std::string one = run_case("upsetting_friction", common + "1", 0, "_1");
  const std::string two = run_case("upsetting_friction", common + "2", 0, "_2");
  const std::string h1 = read_text(one + "/history.csv"), h2 = read_text(two + "/history.csv");
  ASSERT_GT(h1.size(), 100u);
  EXPECT_EQ(h1, h2);
  // Fields: the last step's coordinates, velocities and strains, via h5dump's
  // text (every digit of every value).
  const auto dump = [](const std::string& dir) {
    std::string text;
    const std::string cmd = "h5dump -m %.17g -d /steps/000010/velocity -d /steps/000010/strain -d "
                            "/steps/000010/coordinates " + dir + "/result.h5";
    FILE* p = popen(cmd.c_str(), "r");
    char buf[4096];
    while (p && fgets(buf, sizeof buf, p)) text += buf;
    if (p) pclose(p);
    return text.substr(text.find("DATA"));
  };
  const std::string f1 = dump(one), f2 = dump(two);
  EXPECT_GT(f1.size(), 1000u);
  EXPECT_EQ(f1, f2);
}
