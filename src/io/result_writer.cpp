#include "io/result_writer.hpp"

#include <hdf5.h>

#include "io/hdf5_handles.hpp"
#include "io/xdmf_writer.hpp"

#include <algorithm>
#include <chrono>
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

// The units of the fields a formulation or the driver adds under node/ and
// element/ (docs/case-format.md, [contact]). A field missing here is
// written with units "unknown" (tests/cli/visualization.sh fails on it):
// a run is not stopped for a label.
const char* extra_units(const std::string& name) {
  if (name == "contact_pressure" || name == "contact_shear" || name == "flow_stress") return "MPa";
  if (name == "slip_velocity") return "mm/s";
  if (name == "contact_gap") return "mm";
  if (name == "strain_rate_error") return "1/s";
  return "unknown";
}

// A virtual dataset: rows [first, first + rows) of the dataset `source`
// (total_rows x cols, cols 1 for a vector) of this same file, read as a
// dataset of its own (HDF5 1.10 virtual datasets: nothing is copied).
void write_view(hid_t parent, const std::string& name, const std::string& source, hid_t type, hsize_t total_rows,
                hsize_t first, hsize_t rows, hsize_t cols, const char* units) {
  const int rank = cols > 1 ? 2 : 1;
  const hsize_t dims[2] = {rows, cols}, src_dims[2] = {total_rows, cols}, start[2] = {first, 0};
  H space(H5Screate_simple(rank, dims, nullptr), H5Sclose, "dataspace " + name);
  H src(H5Screate_simple(rank, src_dims, nullptr), H5Sclose, "dataspace " + source);
  check(H5Sselect_hyperslab(src.id, H5S_SELECT_SET, start, nullptr, dims, nullptr), "select " + source);
  H dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "dataset properties");
  check(H5Pset_virtual(dcpl.id, space.id, ".", source.c_str(), src.id), "map " + name);
  H set(H5Dcreate2(parent, name.c_str(), type, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose,
        "create " + name);
  set_attr_string(set.id, "units", units);
}

H group(hid_t parent, const std::string& name) {
  return H(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, name);
}

// File access with a metadata cache of a fixed 1 MB. HDF5's default cache
// grows to hold every object header and attribute written, and each flush
// walks all of it (H5C_set_slist_enabled: 13.7 % of a 200-step run
// recording every step); at 1600 recorded steps a step's HDF5 writes took
// 9.9 ms, 5.9 ms with this cache, and grew with the step count no longer
// (docs/benchmarks.md).
void use_fixed_cache(hid_t fapl) {
  H5AC_cache_config_t c;
  c.version = H5AC__CURR_CACHE_CONFIG_VERSION;
  check(H5Pget_mdc_config(fapl, &c), "metadata cache configuration");
  c.set_initial_size = true;
  c.initial_size = c.max_size = 1 << 20;
  c.min_size = std::min<std::size_t>(c.min_size, c.initial_size);
  c.incr_mode = H5C_incr__off;
  c.flash_incr_mode = H5C_flash_incr__off;
  c.decr_mode = H5C_decr__off;
  check(H5Pset_mdc_config(fapl, &c), "metadata cache configuration");
}

}  // namespace

// result.h5 and its spare, result.h5.spare: two files of the same content.
// HDF5 updates a file's metadata in place, so a run killed while a flush
// reaches the disk can leave a file HDF5 cannot open (and the link storage
// of /steps is shared by every step: every step is lost). So every change
// is written into the spare first; once the spare's flush has finished, the
// two names are exchanged and the change is written into the other file.
// result.h5 is always a file whose last flush finished.
struct ResultWriter::Impl {
  std::string dir;
  hid_t files[2] = {-1, -1};
  int named = 0;                 // files[named] is result.h5
  std::vector<XdmfMesh> meshes;  // the last one current
  std::string paraview;             // result.xdmf's step grids
  std::vector<std::string> meshio;  // per mesh: its meshio file's step grids
  std::vector<int> step_numbers;
  std::vector<double> times;
  std::vector<std::pair<std::string, Index>> die_points;  // per die written: its polyline's points
  // The XDMF files are rewritten whole (atomically), so at most once per
  // kXdmfInterval of the run's time, and when the mesh changes, the
  // metadata is updated (a run's end) or the writer is closed: rewriting
  // them at every one of 1600 recorded steps took 13 s of a 41 s run.
  static constexpr std::chrono::milliseconds kXdmfInterval{1000};
  std::chrono::steady_clock::time_point xdmf_written{};  // the clock's epoch: never
  bool xdmf_behind = false;                               // steps not in them yet

  std::string path(const char* suffix = "") const { return dir + "/result.h5" + suffix; }
  template <class Write>
  void commit(const Write& write);
  void exchange_names() const;
  XdmfMesh write_mesh(hid_t file, const std::string& group, const Mesh& m) const;
  void write_bodies(hid_t step, const std::string& name, const XdmfStep& s) const;
  void write_dies(hid_t file, hid_t step, const StepFields& f,
                  const std::vector<std::pair<std::string, Index>>& new_dies) const;
  void write_xdmf();
  void catch_up_xdmf() {
    if (xdmf_behind) write_xdmf();
  }
};

template <class Write>
void ResultWriter::Impl::commit(const Write& write) {
  for (int pass = 0; pass < 2; ++pass) {
    const hid_t spare = files[1 - named];
    write(spare);
    check(H5Fflush(spare, H5F_SCOPE_GLOBAL), "flush");
    if (pass == 0) exchange_names(), named = 1 - named;
  }
}

// result.h5 <-> result.h5.spare. Each rename replaces its target at once,
// and the hard link keeps result.h5 naming a whole file in between. On a
// file system without hard links result.h5 is renamed away first: between
// two renames it is missing (and a kill there leaves it as
// result.h5.previous, a whole file).
void ResultWriter::Impl::exchange_names() const {
  namespace fs = std::filesystem;
  fs::remove(path(".previous"));
  std::error_code no_link;
  fs::create_hard_link(path(), path(".previous"), no_link);
  if (no_link) fs::rename(path(), path(".previous"));
  fs::rename(path(".spare"), path());
  fs::rename(path(".previous"), path(".spare"));
}

XdmfMesh ResultWriter::Impl::write_mesh(hid_t file, const std::string& name, const Mesh& m) const {
  H g = group(file, name);
  std::vector<long long> conn;
  for (const auto& q : m.quads)
    for (Index n : q) conn.push_back(n);
  write_array(g.id, "connectivity", conn.data(), H5T_NATIVE_LLONG, {hsize_t(m.num_elements()), 4}, "1");
  write_array(g.id, "element_body", m.element_body.data(), H5T_NATIVE_INT, {hsize_t(m.num_elements())}, "1");
  write_doubles(g.id, "initial_coordinates", flatten(m.x), 2, "mm");
  std::string names;
  for (const auto& b : m.body_names) names += (names.empty() ? "" : ";") + b;
  set_attr_string(g.id, "body_names", names);
  // Each body's connectivity numbered within its own nodes (a body's block
  // in result.xdmf has its nodes only).
  XdmfMesh xm{name, m.num_nodes(), m.num_elements(), {}};
  H bodies = group(g.id, "bodies");
  for (int b = 0; b < m.num_bodies(); ++b) {
    XdmfBody xb{m.body_names[b], 0, 0, 0, 0};
    for (Index n = 0; n < m.num_nodes(); ++n)
      if (m.node_body[n] == b && xb.nodes++ == 0) xb.first_node = n;
    for (Index e = 0; e < m.num_elements(); ++e)
      if (m.element_body[e] == b && xb.elements++ == 0) xb.first_element = e;
    std::vector<long long> local;
    for (Index e = xb.first_element; e < xb.first_element + xb.elements; ++e)
      for (Index n : m.quads[e]) {
        if (m.element_body[e] != b || n < xb.first_node || n >= xb.first_node + xb.nodes)
          throw std::logic_error("body '" + xb.name + "': its nodes or elements are not contiguous");
        local.push_back(n - xb.first_node);
      }
    H bg = group(bodies.id, xb.name);
    write_array(bg.id, "connectivity", local.data(), H5T_NATIVE_LLONG, {hsize_t(xb.elements), 4}, "1");
    for (const auto& [key, v] : {std::pair<const char*, Index>{"first_node", xb.first_node}, {"nodes", xb.nodes},
                                 {"first_element", xb.first_element}, {"elements", xb.elements}})
      set_attr(bg.id, key, static_cast<long long>(v), H5T_NATIVE_LLONG);
    xm.bodies.push_back(xb);
  }
  return xm;
}

ResultWriter::ResultWriter(const std::string& dir, const Mesh& mesh, const std::string& metadata_json)
    : impl_(std::make_unique<Impl>()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  std::filesystem::create_directories(dir);
  Impl& w = *impl_;
  w.dir = dir;
  // result.h5 is created as result.h5.partial and renamed once its mesh
  // and metadata are on disk: result.h5 is never a file HDF5 cannot open.
  const std::string partial = w.path(".partial");
  const H access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
  use_fixed_cache(access.id);
  allow_large_attributes(access.id);  // /metadata's JSON grows with the run's events
  for (int i = 0; i < 2; ++i) {
    const std::string name = i == 0 ? partial : w.path(".spare");
    w.files[i] = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id);
    if (w.files[i] < 0) throw std::runtime_error("cannot create " + name);
    const XdmfMesh m = w.write_mesh(w.files[i], "/mesh", mesh);
    if (i == 0) w.meshes.push_back(m);
    H md(create_group_for_large_attributes(w.files[i], "/metadata"), H5Gclose, "/metadata");
    set_attr_string(md.id, "json", metadata_json);
    group(w.files[i], "/steps");
    check(H5Fflush(w.files[i], H5F_SCOPE_GLOBAL), "flush");
  }
  std::filesystem::rename(partial, w.path());
}

// The spare is removed: a finished run leaves result.h5 alone. The XDMF
// files are brought up to date where they can be (a run that ends by an
// exception gets here without update_metadata).
ResultWriter::~ResultWriter() {
  Impl& w = *impl_;
  try {
    w.catch_up_xdmf();
  } catch (const std::exception&) {
  }
  if (w.files[1 - w.named] >= 0) H5Fclose(w.files[1 - w.named]);
  std::error_code ec;
  std::filesystem::remove(w.path(".spare"), ec);
  if (w.files[w.named] >= 0) H5Fclose(w.files[w.named]);
}

int ResultWriter::steps_written() const { return static_cast<int>(impl_->step_numbers.size()); }

void ResultWriter::set_mesh(const Mesh& mesh, int first_step) {
  impl_->catch_up_xdmf();  // the old mesh's meshio file whole
  const std::string name = numbered_group("/meshes", first_step);
  XdmfMesh m;
  impl_->commit([&](hid_t file) {
    if (H5Lexists(file, "/meshes", H5P_DEFAULT) <= 0) group(file, "/meshes");
    m = impl_->write_mesh(file, name, mesh);
  });
  impl_->meshes.push_back(m);
}

void ResultWriter::update_metadata(const std::string& json) {
  impl_->catch_up_xdmf();
  impl_->commit([&](hid_t file) {
    H md(H5Gopen2(file, "/metadata", H5P_DEFAULT), H5Gclose, "/metadata");
    set_attr_string(md.id, "json", json);
  });
}

// Each body's share of the step's fields, as views of them: bodies/<name>/...
void ResultWriter::Impl::write_bodies(hid_t step, const std::string& name, const XdmfStep& s) const {
  const XdmfMesh& m = meshes.back();
  H bodies = group(step, "bodies");
  for (const XdmfBody& b : m.bodies) {
    H bg = group(bodies.id, b.name);
    auto node = [&](const std::string& f, hsize_t cols, const char* units) {
      write_view(bg.id, f, name + "/" + f, H5T_NATIVE_DOUBLE, m.nodes, b.first_node, b.nodes, cols, units);
    };
    auto element = [&](const std::string& f, const std::string& source, hid_t type, const char* units) {
      write_view(bg.id, f, source, type, m.elements, b.first_element, b.elements, 1, units);
    };
    node("coordinates", 2, "mm");
    node("velocity", 2, "mm/s");
    node("velocity_xyz", 3, "mm/s");
    element("strain_rate", name + "/strain_rate", H5T_NATIVE_DOUBLE, "1/s");
    element("strain", name + "/strain", H5T_NATIVE_DOUBLE, "1");
    element("mean_stress", name + "/mean_stress", H5T_NATIVE_DOUBLE, "MPa");
    element("body", m.group + "/element_body", H5T_NATIVE_INT, "1");
    if (!s.node_extra.empty()) group(bg.id, "node");
    if (!s.element_extra.empty()) group(bg.id, "element");
    for (const auto& k : s.node_extra) node("node/" + k, 1, extra_units(k));
    for (const auto& k : s.element_extra) element("element/" + k, name + "/element/" + k, H5T_NATIVE_DOUBLE, extra_units(k));
  }
}

// The dies' polylines at the step (dies/<name>/coordinates); the segments
// joining them once per die, with the die's first polyline
// (/dies/<name>/connectivity).
void ResultWriter::Impl::write_dies(hid_t file, hid_t step, const StepFields& f,
                                    const std::vector<std::pair<std::string, Index>>& new_dies) const {
  if (f.dies.empty()) return;
  H dies = group(step, "dies");
  for (const auto& [die, points] : f.dies) {
    H dg = group(dies.id, die);
    write_doubles(dg.id, "coordinates", flatten(points), 2, "mm");
    const std::string& name = die;  // a structured binding cannot be captured before C++20's clang 16
    if (std::none_of(new_dies.begin(), new_dies.end(), [&](const auto& d) { return d.first == name; })) continue;
    if (H5Lexists(file, "/dies", H5P_DEFAULT) <= 0) group(file, "/dies");
    H top(H5Gopen2(file, "/dies", H5P_DEFAULT), H5Gclose, "/dies");
    H cg = group(top.id, die);
    std::vector<long long> seg;
    for (Index i = 0; i + 1 < static_cast<Index>(points.size()); ++i) seg.insert(seg.end(), {i, i + 1});
    write_array(cg.id, "connectivity", seg.data(), H5T_NATIVE_LLONG, {hsize_t(seg.size() / 2), 2}, "1");
  }
}

void ResultWriter::write_step(const StepFields& f) {
  Impl& w = *impl_;
  // Validate everything before writing anything.
  const auto x = flatten(*f.x), v = flatten(*f.v), v3 = flatten(*f.v, 3);
  require_finite(x, "coordinates");
  require_finite(v, "velocity");
  require_finite(*f.strain_rate, "strain_rate");
  require_finite(*f.strain, "strain");
  require_finite(*f.mean_stress, "mean_stress");
  for (const auto& [k, d] : f.node_scalars) require_finite(d, k);
  for (const auto& [k, d] : f.element_scalars) require_finite(d, k);
  for (const auto& [k, d] : f.globals) require_finite({d}, k);
  std::vector<std::pair<std::string, Index>> new_dies;  // dies first seen here, their points
  for (const auto& [die, p] : f.dies) {
    require_finite(flatten(p), "die " + die);
    if (p.size() < 2) throw std::logic_error("die '" + die + "': a polyline of fewer than two points");
    const std::string& name = die;  // a structured binding cannot be captured before C++20's clang 16
    auto known = std::find_if(w.die_points.begin(), w.die_points.end(), [&](const auto& d) { return d.first == name; });
    if (known == w.die_points.end())
      new_dies.push_back({die, static_cast<Index>(p.size())});
    else if (known->second != static_cast<Index>(p.size()))
      throw std::logic_error("die '" + die + "': its polyline changed its number of points");
  }
  if (!std::isfinite(f.time) || !std::isfinite(f.stroke)) throw std::logic_error("non-finite time or stroke");
  const XdmfMesh& mesh = w.meshes.back();
  if (static_cast<Index>(f.x->size()) != mesh.nodes || static_cast<Index>(f.strain->size()) != mesh.elements)
    throw std::logic_error("a step's fields are not on the current mesh");

  XdmfStep s{f.step, f.time, f.stroke, {}, {}, f.globals, {}};
  for (const auto& [k, d] : f.node_scalars) s.node_extra.push_back(k);
  for (const auto& [k, d] : f.element_scalars) s.element_extra.push_back(k);
  for (const auto& [die, p] : f.dies) s.dies.push_back({die, static_cast<Index>(p.size())});
  // The index of recorded steps and their times (a failed write ends the run).
  w.step_numbers.push_back(f.step);
  w.times.push_back(f.time);
  const std::string name = numbered_group("/steps", f.step);
  w.commit([&](hid_t file) {
    H g = group(file, name);
    set_attr(g.id, "step", f.step, H5T_NATIVE_INT);
    set_attr(g.id, "time", f.time, H5T_NATIVE_DOUBLE);
    set_attr(g.id, "stroke", f.stroke, H5T_NATIVE_DOUBLE);
    set_attr_string(g.id, "mesh", mesh.group);
    write_doubles(g.id, "coordinates", x, 2, "mm");
    write_doubles(g.id, "velocity", v, 2, "mm/s");
    write_doubles(g.id, "velocity_xyz", v3, 3, "mm/s");
    write_doubles(g.id, "strain_rate", *f.strain_rate, 1, "1/s");
    write_doubles(g.id, "strain", *f.strain, 1, "1");
    write_doubles(g.id, "mean_stress", *f.mean_stress, 1, "MPa");
    if (!f.node_scalars.empty()) {
      H n = group(g.id, "node");
      for (const auto& [k, d] : f.node_scalars) write_doubles(n.id, k, d, 1, extra_units(k));
    }
    if (!f.element_scalars.empty()) {
      H e = group(g.id, "element");
      for (const auto& [k, d] : f.element_scalars) write_doubles(e.id, k, d, 1, extra_units(k));
    }
    w.write_bodies(g.id, name, s);
    w.write_dies(file, g.id, f, new_dies);
    // The index of recorded steps and their times, rewritten each step.
    H steps(H5Gopen2(file, "/steps", H5P_DEFAULT), H5Gclose, "/steps");
    for (const char* n : {"index", "time"})
      if (H5Lexists(steps.id, n, H5P_DEFAULT) > 0) check(H5Ldelete(steps.id, n, H5P_DEFAULT), "delete index");
    write_array(steps.id, "index", w.step_numbers.data(), H5T_NATIVE_INT, {w.step_numbers.size()}, "1");
    write_doubles(steps.id, "time", w.times, 1, "s");
  });
  w.die_points.insert(w.die_points.end(), new_dies.begin(), new_dies.end());
  w.paraview += paraview_xdmf(mesh, s);
  w.meshio.resize(w.meshes.size());
  w.meshio.back() += meshio_xdmf(mesh, s);
  w.xdmf_behind = true;
  const bool first = w.xdmf_written == std::chrono::steady_clock::time_point{};
  if (first || std::chrono::steady_clock::now() - w.xdmf_written >= Impl::kXdmfInterval) w.write_xdmf();
}

// result.xdmf whole, and the meshio file of the current mesh (the earlier
// meshes' are complete).
void ResultWriter::Impl::write_xdmf() {
  write_text_atomically(dir + "/result.xdmf", {kXdmfHead, paraview, kXdmfTail});
  write_text_atomically(dir + "/" + meshio_file_name(meshes.back().group), {kXdmfHead, meshio.back(), kXdmfTail});
  xdmf_written = std::chrono::steady_clock::now();
  xdmf_behind = false;
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
  write_text_atomically(path, {std::string_view(text)});
}

void write_text_atomically(const std::string& path, std::initializer_list<std::string_view> pieces) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    for (std::string_view p : pieces) out << p;
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace rpfem
