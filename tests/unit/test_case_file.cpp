// Case-file validation: types, ranges, unknown keys, overrides, the record
// of used values (defaults included), and the whole scene reader.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/case_file.hpp"
#include "io/scene_reader.hpp"

#include "temp_file.hpp"

using namespace rpfem;

namespace {
std::string write(const std::string& name, const std::string& text) { return unit::write_temp(name, text); }
}  // namespace

TEST(CaseFile, ReadsValidatesAndRecordsDefaults) {
  CaseFile f(write("cf1.toml", "[a]\nx = 2\ny = \"u\"\n"));
  auto a = f.root().required_table("a");
  EXPECT_EQ(a.real("x", std::nullopt, Range::positive()), 2.0);  // integer accepted as a number
  EXPECT_EQ(a.text("y", std::nullopt, {"u", "v"}), "u");
  EXPECT_EQ(a.real("z", 7.5, Range::any()), 7.5);
  EXPECT_NO_THROW(f.finish());
  const std::string json = f.used_json();
  EXPECT_NE(json.find("\"z\""), std::string::npos);  // the default is recorded
  EXPECT_NE(json.find("7.5"), std::string::npos);
}

TEST(CaseFile, ErrorsNameFileKeyAndExpectation) {
  CaseFile f(write("cf2.toml", "[a]\nx = -1.0\nw = \"q\"\nextra = 1\n"));
  auto a = f.root().required_table("a");
  try {
    a.real("x", std::nullopt, Range::positive(), "MPa");
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("cf2.toml"), std::string::npos);
    EXPECT_NE(m.find("'a.x'"), std::string::npos);
    EXPECT_NE(m.find("positive number (MPa)"), std::string::npos);
  }
  EXPECT_THROW(a.text("w", std::nullopt, {"u", "v"}), InputError);
  EXPECT_THROW(a.integer("missing", std::nullopt, 0, 3), InputError);
  try {
    f.finish();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'a.extra'"), std::string::npos);
  }
}

TEST(CaseFile, OverridesReplaceAndCreate) {
  CaseFile f(write("cf3.toml", "[a]\nx = 1.0\n[[a.list]]\nv = 1\n"),
             {"a.x=3.5", "a.new=\"s\"", "a.list.0.v=4", "b.c=word"});
  auto a = f.root().required_table("a");
  EXPECT_EQ(a.real("x", std::nullopt, Range::any()), 3.5);
  EXPECT_EQ(a.text("new", std::nullopt), "s");
  EXPECT_EQ(a.table_array("list")[0].integer("v", std::nullopt, 0, 9), 4);
  EXPECT_EQ(f.root().required_table("b").text("c", std::nullopt), "word");
  EXPECT_THROW(CaseFile(write("cf4.toml", "x = 1\n"), {"x.y=2"}), InputError);
  EXPECT_THROW(CaseFile(write("cf5.toml", "x = 1\n"), {"novalue"}), InputError);
}

TEST(CaseFile, MalformedAndMissing) {
  EXPECT_THROW(CaseFile("/nonexistent/case.toml"), InputError);
  EXPECT_THROW(CaseFile(write("cf6.toml", "[a\n")), InputError);
}

TEST(SceneReader, ShippedUpsettingCase) {
  CaseFile f(std::string(RPFEM_SOURCE_DIR) + "/cases/upsetting_frictionless_axisym.toml");
  const Scene s = read_scene(f);
  EXPECT_NO_THROW(f.finish());
  EXPECT_EQ(s.geometry, Geometry::Axisymmetric);
  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_NEAR(s.bodies[0].law.K, 91.97 * 9.80665, 1e-9);  // kgf/mm^2 converted at input
  EXPECT_EQ(s.mesh.num_elements(), 400);
  ASSERT_EQ(s.velocities.size(), 1u);
  EXPECT_FALSE(s.velocities[0].vx.has_value());  // frictionless: sliding platen
  EXPECT_EQ(s.symmetry.size(), 1u);
  EXPECT_EQ(s.stepping.reference, "top_platen");
  EXPECT_NE(f.used_json().find("\"alpha\""), std::string::npos);  // solver defaults recorded
}

TEST(SceneReader, MeshFactorScalesEveryBodysDivisions) {
  // The Test II scene: billet 20 x 20, punch 20 x 4 divisions; at 0.5 they
  // halve (400 + 80 elements -> 100 + 20), and the factor is recorded.
  CaseFile f(std::string(RPFEM_SOURCE_DIR) + "/cases/paper_test2_virtual_rigid.toml", {"run.mesh_factor=0.5"});
  const Scene s = read_scene(f);
  EXPECT_EQ(s.mesh.num_elements(), 120);
  EXPECT_DOUBLE_EQ(f.used().at_path("run.mesh_factor").value_or(0.0), 0.5);
  CaseFile g(std::string(RPFEM_SOURCE_DIR) + "/cases/paper_test2_virtual_rigid.toml", {"run.mesh_factor=0"});
  EXPECT_THROW(read_scene(g), InputError);
}

TEST(SceneReader, RejectsBodiesAcrossTheAxis) {
  const std::string p = write("cf7.toml", R"([run]
geometry = "axisymmetric"
[bodies.b.material]
K = 100.0
n = 0.1
[bodies.b.mesh]
shape = "rectangle"
x0 = -1.0
width = 2.0
height = 1.0
nx = 2
ny = 2
[stepping]
end_stroke = 1.0
stroke_increment = 0.1
reference = "x"
)");
  CaseFile f(p);
  EXPECT_THROW(read_scene(f), InputError);
}

TEST(SceneReader, VirtualRigidBodyOfTestII) {
  CaseFile f(std::string(RPFEM_SOURCE_DIR) + "/cases/paper_test2_virtual_rigid.toml");
  const Scene s = read_scene(f);
  EXPECT_NO_THROW(f.finish());
  ASSERT_EQ(s.bodies.size(), 2u);
  for (const BodySpec& b : s.bodies) {
    if (b.name == "punch") {
      EXPECT_NEAR(b.law.K, 1e5 * 9.80665, 1e-6);  // the paper's K = 1e5 kgf/mm^2
      EXPECT_NEAR(b.law.n, 1e-4, 1e-15);
      ASSERT_TRUE(b.alpha_relative.has_value());   // its own volumetric penalty
      EXPECT_EQ(*b.alpha_relative, 1e2);
    } else {
      EXPECT_FALSE(b.alpha_relative.has_value());  // solver.alpha
    }
  }
  ASSERT_EQ(s.contact_pairs.size(), 2u);
  EXPECT_EQ(s.contact_pairs[0].friction.kind, FrictionLaw::Kind::Coulomb);
  EXPECT_NEAR(s.contact_pairs[0].friction.mu, 0.1, 1e-15);
}
