// result.h5 / result.xdmf / history.csv: layout, values, flushing per step,
// refusal of non-finite values.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

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
  }
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
  EXPECT_NE(xdmf.find("result.h5:/steps/000000/coordinates"), std::string::npos);
  EXPECT_NE(xdmf.find("result.h5:/steps/000001/strain_rate"), std::string::npos);
  EXPECT_EQ(xdmf.find("000002"), std::string::npos);
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
