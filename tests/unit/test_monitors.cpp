// Monitors: validation against the mesh and their values on a moved mesh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/case_file.hpp"
#include "io/monitors.hpp"
#include "mesh/generate.hpp"

#include "temp_file.hpp"

using namespace rpfem;

namespace {
std::string write(const std::string& name, const std::string& text) { return unit::write_temp(name, text); }
Mesh block() {
  RectangleSpec r;
  r.width = 4;
  r.height = 2;
  r.nx = 4;
  r.ny = 2;
  return make_rectangle("b", r);
}
std::string error_of(const std::string& text) {
  CaseFile f(write("mon_err.toml", text));
  try {
    read_monitors(f.root(), block());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Monitors, ValuesAndChangesOnAMovedMesh) {
  CaseFile f(write("mon.toml", R"(
[[monitors]]
name = "right_max"
side = "b.right"
quantity = "max_x"
[[monitors]]
name = "mid_right"
side = "b.right"
quantity = "x_near"
at = [4.0, 1.1]
change = "percent"
[[monitors]]
name = "top"
side = "b.top"
quantity = "min_y"
change = "relative"
)"));
  const Mesh m = block();
  const auto mons = read_monitors(f.root(), m);
  EXPECT_NO_THROW(f.finish());
  ASSERT_EQ(mons.size(), 3u);
  ASSERT_EQ(mons[1].nodes.size(), 1u);
  EXPECT_EQ(m.x[mons[1].nodes[0]], Vec2(4, 1));  // the side node nearest (4, 1.1)
  std::vector<Vec2> x = m.x;
  EXPECT_EQ(evaluate_monitors(mons, x), (std::vector<double>{4.0, 0.0, 0.0}));
  // Bulge the right side at mid-height by 0.5 mm, lower the top by 0.2 mm
  // except one node.
  x[mons[1].nodes[0]](0) += 0.5;
  for (Index n : m.side_nodes("b.top")) x[n](1) -= 0.2;
  x[m.side_nodes("b.top")[2]](1) -= 0.3;
  const auto v = evaluate_monitors(mons, x);
  EXPECT_DOUBLE_EQ(v[0], 4.5);
  EXPECT_DOUBLE_EQ(v[1], 100 * 0.5 / 4);
  EXPECT_DOUBLE_EQ(v[2], 1.5 / 2 - 1);
}

TEST(Monitors, BadDefinitionsNameTheKey) {
  const std::string head = "[[monitors]]\nname = \"a\"\n";
  EXPECT_NE(error_of(head + "side = \"b.nope\"\nquantity = \"min_x\"\n").find("monitors.0.side"), std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.nope\"\nquantity = \"min_x\"\n").find("b.right"), std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.top\"\nquantity = \"x_near\"\n").find("monitors.0.at"), std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.top\"\nquantity = \"x_near\"\nat = [1.0]\n").find("2 numbers"),
            std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.top\"\nquantity = \"mean_x\"\n").find("monitors.0.quantity"),
            std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.left\"\nquantity = \"min_x\"\nchange = \"percent\"\n").find("initial value is 0"),
            std::string::npos);
  EXPECT_NE(error_of(head + "side = \"b.top\"\nquantity = \"min_x\"\n" + head + "side = \"b.top\"\nquantity = \"min_y\"\n")
                .find("unique"),
            std::string::npos);
}
