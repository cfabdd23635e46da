#include "io/result_writer.hpp"

#include <hdf5.h>

#include "io/hdf5_handles.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rpfem {

using namespace h5;

namespace {

template <class T>
void set_attr(hid_t obj, const std::string& name, T value, hid_t type) {
  H space(H5Screate(H5S_SCALAR), H5Sclose, "scalar space");
  H attr(H5Acreate2(obj, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, "attribute " + name);
  check(H5Awrite(attr.id, type, &value), "write attribute " + name);
}

std::vector<double> flatten(const std::vector<Vec2>& v, int width = 2) {
  std::vector<double> out;
  out.reserve(v.size() * width);
  for (const auto& p : v) {
    out.push_back(p(0));
    out.push_back(p(1));
    if (width == 3) out.push_back(0.0);
  }
  return out;
}

void require_finite(const std::vector<double>& v, const std::string& name) {
  for (double x : v)
    if (!std::isfinite(x)) throw std::logic_error("result field '" + name + "' holds a non-finite value");
}

}  // namespace

struct ResultWriter::Impl {
  std::string dir;
  hid_t file = -1;
  Index nn = 0, ne = 0;        // the current mesh's nodes and elements
  std::string mesh = "/mesh";  // the current mesh's group
  std::vector<int> steps;
  std::vector<double> times;
  std::vector<std::string> step_mesh;            // per step: its mesh group
  std::vector<std::pair<Index, Index>> step_size;  // per step: nodes, elements
  std::vector<std::vector<std::string>> node_extra, element_extra;
  void write_mesh(const std::string& group, const Mesh& m);
  void write_xdmf() const;
};

void ResultWriter::Impl::write_mesh(const std::string& group, const Mesh& m) {
  H g(H5Gcreate2(file, group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, group);
  std::vector<long long> conn;
  for (const auto& q : m.quads)
    for (Index n : q) conn.push_back(n);
  write_array(g.id, "connectivity", conn.data(), H5T_NATIVE_LLONG, {hsize_t(m.num_elements()), 4});
  write_array(g.id, "element_body", m.element_body.data(), H5T_NATIVE_INT, {hsize_t(m.num_elements())});
  write_doubles(g.id, "initial_coordinates", flatten(m.x), 2);
  std::string names;
  for (const auto& b : m.body_names) names += (names.empty() ? "" : ";") + b;
  set_attr_string(g.id, "body_names", names);
  mesh = group, nn = m.num_nodes(), ne = m.num_elements();
}

ResultWriter::ResultWriter(const std::string& dir, const Mesh& mesh, const std::string& metadata_json)
    : impl_(std::make_unique<Impl>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::filesystem::create_directories(dir);
  impl_->dir = dir;
  // Created as result.h5.partial and renamed once its mesh and metadata
  // are on disk: result.h5 is never a file HDF5 cannot open.
  const std::string path = dir + "/result.h5", partial = path + ".partial";
  impl_->file = H5Fcreate(partial.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (impl_->file < 0) throw std::runtime_error("cannot create " + partial);
  impl_->write_mesh("/mesh", mesh);
  {
    H md(H5Gcreate2(impl_->file, "/metadata", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "/metadata");
    set_attr_string(md.id, "json", metadata_json);
    H st(H5Gcreate2(impl_->file, "/steps", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "/steps");
  }
  check(H5Fflush(impl_->file, H5F_SCOPE_GLOBAL), "flush");
  std::filesystem::rename(partial, path);
}

ResultWriter::~ResultWriter() {
  if (impl_->file >= 0) H5Fclose(impl_->file);
}

int ResultWriter::steps_written() const { return static_cast<int>(impl_->steps.size()); }

void ResultWriter::set_mesh(const Mesh& mesh, int first_step) {
  char name[40];
  std::snprintf(name, sizeof name, "/meshes/%06d", first_step);
  if (H5Lexists(impl_->file, "/meshes", H5P_DEFAULT) <= 0)
    H(H5Gcreate2(impl_->file, "/meshes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "/meshes");
  impl_->write_mesh(name, mesh);
  check(H5Fflush(impl_->file, H5F_SCOPE_GLOBAL), "flush");
}

void ResultWriter::update_metadata(const std::string& json) {
  H md(H5Gopen2(impl_->file, "/metadata", H5P_DEFAULT), H5Gclose, "/metadata");
  set_attr_string(md.id, "json", json);
  check(H5Fflush(impl_->file, H5F_SCOPE_GLOBAL), "flush");
}

void ResultWriter::write_step(const StepFields& f) {
  // Validate everything before writing anything.
  const auto x = flatten(*f.x), v = flatten(*f.v), v3 = flatten(*f.v, 3);
  require_finite(x, "coordinates");
  require_finite(v, "velocity");
  require_finite(*f.strain_rate, "strain_rate");
  require_finite(*f.strain, "strain");
  require_finite(*f.mean_stress, "mean_stress");
  for (const auto& [k, d] : f.node_scalars) require_finite(d, k);
  for (const auto& [k, d] : f.element_scalars) require_finite(d, k);
  if (!std::isfinite(f.time) || !std::isfinite(f.stroke)) throw std::logic_error("non-finite time or stroke");
  if (static_cast<Index>(f.x->size()) != impl_->nn || static_cast<Index>(f.strain->size()) != impl_->ne)
    throw std::logic_error("a step's fields are not on the current mesh");

  char name[32];
  std::snprintf(name, sizeof name, "/steps/%06d", f.step);
  H g(H5Gcreate2(impl_->file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, name);
  set_attr(g.id, "step", f.step, H5T_NATIVE_INT);
  set_attr(g.id, "time", f.time, H5T_NATIVE_DOUBLE);
  set_attr(g.id, "stroke", f.stroke, H5T_NATIVE_DOUBLE);
  set_attr_string(g.id, "mesh", impl_->mesh);
  write_doubles(g.id, "coordinates", x, 2);
  write_doubles(g.id, "velocity", v, 2);
  write_doubles(g.id, "velocity_xyz", v3, 3);
  write_doubles(g.id, "strain_rate", *f.strain_rate);
  write_doubles(g.id, "strain", *f.strain);
  write_doubles(g.id, "mean_stress", *f.mean_stress);
  std::vector<std::string> nk, ek;
  if (!f.node_scalars.empty()) {
    H n(H5Gcreate2(g.id, "node", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "node");
    for (const auto& [k, d] : f.node_scalars) write_doubles(n.id, k, d), nk.push_back(k);
  }
  if (!f.element_scalars.empty()) {
    H e(H5Gcreate2(g.id, "element", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "element");
    for (const auto& [k, d] : f.element_scalars) write_doubles(e.id, k, d), ek.push_back(k);
  }
  impl_->steps.push_back(f.step);
  impl_->times.push_back(f.time);
  impl_->step_mesh.push_back(impl_->mesh);
  impl_->step_size.push_back({impl_->nn, impl_->ne});
  impl_->node_extra.push_back(nk);
  impl_->element_extra.push_back(ek);
  // The index of recorded steps and their times, rewritten each step.
  H steps(H5Gopen2(impl_->file, "/steps", H5P_DEFAULT), H5Gclose, "/steps");
  for (const char* n : {"index", "time"})
    if (H5Lexists(steps.id, n, H5P_DEFAULT) > 0) check(H5Ldelete(steps.id, n, H5P_DEFAULT), "delete index");
  write_array(steps.id, "index", impl_->steps.data(), H5T_NATIVE_INT, {impl_->steps.size()});
  write_doubles(steps.id, "time", impl_->times);
  check(H5Fflush(impl_->file, H5F_SCOPE_GLOBAL), "flush");
  impl_->write_xdmf();
}

void ResultWriter::Impl::write_xdmf() const {
  std::ostringstream os;
  os << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
     << "  <Grid Name=\"rpfem\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  auto item = [&](const std::string& path, Index rows, int cols) {
    os << "     <DataItem Format=\"HDF\" NumberType=\"Float\" Precision=\"8\" Dimensions=\"" << rows;
    if (cols > 1) os << " " << cols;
    os << "\">result.h5:" << path << "</DataItem>\n";
  };
  for (std::size_t i = 0; i < steps.size(); ++i) {
    char g[32];
    std::snprintf(g, sizeof g, "/steps/%06d", steps[i]);
    const std::string s(g);
    // Each step on its own mesh (a remesh starts a new one).
    const auto [nn, ne] = step_size[i];
    os << "   <Grid Name=\"step " << steps[i] << "\" GridType=\"Uniform\">\n"
       << "    <Time Value=\"" << times[i] << "\"/>\n"
       << "    <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << ne << "\">\n"
       << "     <DataItem Format=\"HDF\" NumberType=\"Int\" Precision=\"8\" Dimensions=\"" << ne
       << " 4\">result.h5:" << step_mesh[i] << "/connectivity</DataItem>\n    </Topology>\n"
       << "    <Geometry GeometryType=\"XY\">\n";
    item(s + "/coordinates", nn, 2);
    os << "    </Geometry>\n    <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n";
    item(s + "/velocity_xyz", nn, 3);
    os << "    </Attribute>\n";
    auto scalar = [&](const std::string& name, const std::string& path, Index rows, const char* center) {
      os << "    <Attribute Name=\"" << name << "\" AttributeType=\"Scalar\" Center=\"" << center << "\">\n";
      item(path, rows, 1);
      os << "    </Attribute>\n";
    };
    for (const char* f : {"strain_rate", "strain", "mean_stress"}) scalar(f, s + "/" + f, ne, "Cell");
    for (const auto& k : node_extra[i]) scalar(k, s + "/node/" + k, nn, "Node");
    for (const auto& k : element_extra[i]) scalar(k, s + "/element/" + k, ne, "Cell");
    os << "   </Grid>\n";
  }
  os << "  </Grid>\n </Domain>\n</Xdmf>\n";
  write_text_atomically(dir + "/result.xdmf", os.str());
}

HistoryWriter::HistoryWriter(const std::string& path, std::vector<std::string> columns)
    : path_(path), ncols_(columns.size()) {
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) header += (i ? "," : "") + columns[i];
  write_text_atomically(path, header + "\n");
}

void HistoryWriter::write_row(const std::vector<double>& values) {
  if (values.size() != ncols_) throw std::logic_error("history row has the wrong number of columns");
  for (double v : values)
    if (!std::isfinite(v)) throw std::logic_error("history row holds a non-finite value");
  std::ofstream out(path_, std::ios::app);
  char buf[32];
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.10g", values[i]);
    out << (i ? "," : "") << buf;
  }
  out << "\n";
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + path_);
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace rpfem
