// result.h5 / result.xdmf / history.csv: layout, values, flushing per step,
// refusal of non-finite values.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <hdf5.h>

#include "io/result_writer.hpp"
#include "mesh/generate.hpp"
#include "results.hpp"

using namespace rpfem;

TEST(ResultWriter, WritesStepsAndRefusesNaN) {
  const std::string dir = (std::filesystem::temp_directory_path() / "rpfem_writer_test").string();
  std::filesystem::remove_all(dir);
  const Mesh mesh = make_rectangle("b", {0, 0, 2, 1, 2, 1});
  std::vector<Vec2> x = mesh.x, v(mesh.x.size(), Vec2(0.5, -1.0));
  std::vector<double> rate{0.1, 0.2}, strain{0.01, 0.02}, sm{-5.0, -6.0};
  {
    ResultWriter w(dir, mesh, "{\"case\":\"t\"}");
    for (int s = 0; s < 2; ++s) {
      StepFields f;
      f.step = s;
      f.time = 0.5 * s;
      f.stroke = 0.1 * s;
      f.x = &x;
      f.v = &v;
      f.strain_rate = &rate;
      f.strain = &strain;
      f.mean_stress = &sm;
      f.element_scalars["flow_stress"] = {100.0, 101.0};
      f.globals = {{"top.Fy", -1000.0 / 3 * s}};
      f.dies = {{"top", {Vec2(0, 1.5 - 0.1 * s), Vec2(2, 1.5 - 0.1 * s)}}};
      w.write_step(f);
    }
    std::vector<double> bad = strain;
    bad[1] = std::nan("");
    StepFields f;
    f.step = 2;
    f.x = &x;
    f.v = &v;
    f.strain_rate = &rate;
    f.strain = &bad;
    f.mean_stress = &sm;
    EXPECT_THROW(w.write_step(f), std::logic_error);
    EXPECT_EQ(w.steps_written(), 2);
    // The spare copy that each step is written into first (so result.h5 is
    // always a file whose last flush finished), and no link left between.
    EXPECT_TRUE(std::filesystem::exists(dir + "/result.h5.spare"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/result.h5.previous"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/result.h5.spare")) << "a finished writer removes its spare";
  const std::string h5 = dir + "/result.h5";
  EXPECT_EQ(read_h5_steps(h5), (std::vector<int>{0, 1}));  // the refused step left nothing
  std::vector<unsigned long long> shape;
  const auto c = read_h5_dataset(h5, "/mesh/connectivity", &shape);
  EXPECT_EQ(shape, (std::vector<unsigned long long>{2, 4}));
  const auto vel = read_h5_dataset(h5, "/steps/000001/velocity", &shape);
  EXPECT_EQ(shape, (std::vector<unsigned long long>{6, 2}));
  EXPECT_EQ(vel[0], 0.5);
  EXPECT_EQ(vel[1], -1.0);
  EXPECT_EQ(read_h5_dataset(h5, "/steps/000001/strain")[1], 0.02);
  EXPECT_EQ(read_h5_dataset(h5, "/steps/000000/element/flow_stress")[1], 101.0);
  const std::string xdmf = read_text(dir + "/result.xdmf");
  EXPECT_NE(xdmf.find("result.h5:/steps/000000/bodies/b/coordinates"), std::string::npos);
  EXPECT_NE(xdmf.find("result.h5:/steps/000001/bodies/b/strain_rate"), std::string::npos);
  EXPECT_EQ(xdmf.find("000002"), std::string::npos);
  // A block per body (its share of the fields a view of the step's), the
  // die's polyline, the step's globals at full precision (the shortest
  // text that reads back as the same double), units.
  EXPECT_EQ(read_h5_dataset(h5, "/steps/000001/bodies/b/strain")[1], 0.02);
  EXPECT_EQ(read_h5_dataset(h5, "/steps/000001/dies/top/coordinates")[1], 1.4);
  EXPECT_NE(xdmf.find("<Grid Name=\"b\" GridType=\"Uniform\">"), std::string::npos);
  EXPECT_NE(xdmf.find("<Grid Name=\"die top\" GridType=\"Uniform\">"), std::string::npos);
  EXPECT_NE(xdmf.find("result.h5:/dies/top/connectivity"), std::string::npos);
  EXPECT_NE(xdmf.find("<Attribute Name=\"top.Fy\" AttributeType=\"Scalar\" Center=\"Grid\"><DataItem Format=\"XML\" "
                      "Dimensions=\"1\">-333.3333333333333</DataItem>"),
            std::string::npos);
  const std::string meshio = read_text(dir + "/result_meshio.xdmf");
  EXPECT_NE(meshio.find("<Attribute Name=\"coordinates\""), std::string::npos);
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const char* d : {"/mesh/connectivity", "/steps/time", "/steps/000001/strain_rate", "/steps/000001/bodies/b/velocity",
                        "/steps/000000/element/flow_stress", "/dies/top/connectivity"})
    EXPECT_GT(H5Aexists_by_name(file, d, "units", H5P_DEFAULT), 0) << d;
  H5Fclose(file);
}

// result.h5's /metadata json grows with a run's events and warnings: written
// at 200 kB and rewritten at 300 kB (past the 64 kB an attribute in its
// object's header can hold), each read back whole.
TEST(ResultWriter, MetadataBeyond64kBIsWrittenAndRewritten) {
  const std::string dir = (std::filesystem::temp_directory_path() / "rpfem_writer_large_metadata").string();
  std::filesystem::remove_all(dir);
  const Mesh mesh = make_rectangle("b", {0, 0, 2, 1, 2, 1});
  const auto json = [](std::size_t n) { return "{\"notes\":\"" + std::string(n, 'x') + "\"}"; };
  {
    ResultWriter w(dir, mesh, json(200000));
    EXPECT_EQ(read_h5_text_attribute(dir + "/result.h5", "/metadata", "json"), json(200000));
    w.update_metadata(json(300000));
  }
  EXPECT_EQ(read_h5_text_attribute(dir + "/result.h5", "/metadata", "json"), json(300000));
}

TEST(HistoryWriter, RowsAndValidation) {
  const std::string p = (std::filesystem::temp_directory_path() / "rpfem_history_test.csv").string();
  HistoryWriter h(p, {"step", "load"});
  h.write_row({0, 1.5});
  h.write_row({1, -2.25e5});
  EXPECT_THROW(h.write_row({2}), std::logic_error);
  EXPECT_THROW(h.write_row({2, std::nan("")}), std::logic_error);
  const History r = read_history(p);
  ASSERT_EQ(r.rows(), 2u);
  EXPECT_EQ(r.at("load")[1], -2.25e5);
  write_text_atomically(p, "x\n");
  EXPECT_EQ(read_text(p), "x\n");
}

TEST(ResultWriter, ARemeshStartsANewMesh) {
  // Steps 0 and 1 on a 2 x 1 mesh, steps 2 and 3 on a 3 x 2 one: result.h5
  // keeps both meshes, each step names its own, and the XDMF grid of each
  // step takes its topology from that mesh.
  const std::string dir = (std::filesystem::temp_directory_path() / "rpfem_writer_remesh_test").string();
  std::filesystem::remove_all(dir);
  const Mesh a = make_rectangle("b", {0, 0, 2, 1, 2, 1}), b = make_rectangle("b", {0, 0, 2, 1, 3, 2});
  {
    ResultWriter w(dir, a, "{}");
    for (int s = 0; s < 4; ++s) {
      const Mesh& m = s < 2 ? a : b;
      if (s == 2) w.set_mesh(b, 2);
      std::vector<Vec2> x = m.x, v(m.x.size(), Vec2(0, -1));
      std::vector<double> e(m.quads.size(), 0.1);
      StepFields f;
      f.step = s;
      f.time = s;
      f.x = &x, f.v = &v, f.strain_rate = &e, f.strain = &e, f.mean_stress = &e;
      w.write_step(f);
      if (s == 3) {  // fields of the old mesh no longer fit
        std::vector<Vec2> old_x = a.x;
        std::vector<double> old_e(a.quads.size(), 0.1);
        f.step = 4, f.x = &old_x, f.v = &old_x, f.strain_rate = &old_e, f.strain = &old_e, f.mean_stress = &old_e;
        EXPECT_THROW(w.write_step(f), std::logic_error);
      }
    }
  }
  const std::string h5 = dir + "/result.h5";
  EXPECT_EQ(read_h5_steps(h5), (std::vector<int>{0, 1, 2, 3}));
  std::vector<unsigned long long> shape;
  read_h5_dataset(h5, "/meshes/000002/connectivity", &shape);
  EXPECT_EQ(shape, (std::vector<unsigned long long>{6, 4}));
  read_h5_dataset(h5, "/steps/000003/coordinates", &shape);
  EXPECT_EQ(shape, (std::vector<unsigned long long>{12, 2}));
  const auto mesh_of = [&](const char* step) {
    const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t attr = H5Aopen_by_name(f, step, "mesh", H5P_DEFAULT, H5P_DEFAULT);
    const hid_t type = H5Aget_type(attr);
    std::string s(H5Tget_size(type), '\0');
    H5Aread(attr, type, s.data());
    H5Tclose(type), H5Aclose(attr), H5Fclose(f);
    return std::string(s.c_str());
  };
  EXPECT_EQ(mesh_of("/steps/000001"), "/mesh");
  EXPECT_EQ(mesh_of("/steps/000002"), "/meshes/000002");
  const std::string xdmf = read_text(dir + "/result.xdmf");
  EXPECT_NE(xdmf.find("NumberOfElements=\"2\">"), std::string::npos);
  EXPECT_NE(xdmf.find("NumberOfElements=\"6\">"), std::string::npos);
  EXPECT_NE(xdmf.find("Dimensions=\"6 4\">result.h5:/meshes/000002/bodies/b/connectivity"), std::string::npos);
  EXPECT_NE(xdmf.find("Dimensions=\"12 2\">result.h5:/steps/000003/bodies/b/coordinates"), std::string::npos);
  // meshio: a file per mesh, the first one's steps in result_meshio.xdmf.
  const std::string first = read_text(dir + "/result_meshio.xdmf"), second = read_text(dir + "/result_meshio_000002.xdmf");
  EXPECT_NE(first.find("result.h5:/steps/000001/coordinates"), std::string::npos);
  EXPECT_EQ(first.find("000002"), std::string::npos);
  EXPECT_NE(second.find("Dimensions=\"6 4\">result.h5:/meshes/000002/connectivity"), std::string::npos);
  EXPECT_NE(second.find("Dimensions=\"12 2\">result.h5:/steps/000003/coordinates"), std::string::npos);
  EXPECT_EQ(second.find("000001"), std::string::npos);
}

TEST(ResultWriter, XdmfFilesFollowWithinASecondAndAreWholeAtTheEnd) {
  // result.xdmf is rewritten whole, so not at every step: at the first, then
  // once a second has passed since the last rewrite, and when the metadata
  // is updated (a run's end). In between it names a prefix of the steps in
  // result.h5 (a killed run's result.xdmf opens with what it names).
  const std::string dir = (std::filesystem::temp_directory_path() / "rpfem_writer_xdmf_test").string();
  std::filesystem::remove_all(dir);
  const Mesh mesh = make_rectangle("b", {0, 0, 2, 1, 2, 1});
  std::vector<Vec2> x = mesh.x, v(mesh.x.size(), Vec2(0, -1));
  std::vector<double> e(mesh.quads.size(), 0.1);
  const auto named = [&] {  // the steps result.xdmf names, in order
    const std::string t = read_text(dir + "/result.xdmf");
    std::vector<int> steps;
    const std::string key = "result.h5:/steps/";
    for (std::size_t p = 0; (p = t.find(key, p)) != std::string::npos; p += key.size()) {
      const int s = std::stoi(t.substr(p + key.size(), 6));
      if (steps.empty() || steps.back() != s) steps.push_back(s);
    }
    return steps;
  };
  ResultWriter w(dir, mesh, "{}");
  const auto write = [&](int s) {
    StepFields f;
    f.step = s, f.time = s;
    f.x = &x, f.v = &v, f.strain_rate = &e, f.strain = &e, f.mean_stress = &e;
    w.write_step(f);
  };
  for (int s = 0; s < 5; ++s) {
    write(s);
    const std::vector<int> steps = named();
    ASSERT_FALSE(steps.empty()) << "the first step is written at once";
    ASSERT_LE(steps.size(), std::size_t(s + 1));
    for (std::size_t i = 0; i < steps.size(); ++i) EXPECT_EQ(steps[i], int(i));
  }
  w.update_metadata("{\"status\":\"finished\"}");
  EXPECT_EQ(named(), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(read_text(dir + "/result_meshio.xdmf").find("result.h5:/steps/000004/coordinates") != std::string::npos,
            true);
  // A second after the last rewrite, the next step is written at once.
  std::this_thread::sleep_for(std::chrono::milliseconds(1050));
  write(5);
  EXPECT_EQ(named().back(), 5);
}
