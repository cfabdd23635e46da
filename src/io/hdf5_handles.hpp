// Small RAII and write helpers over HDF5's C API (result files, sweep
// tables).
#pragma once
#include <hdf5.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace rpfem::h5 {

inline void check(herr_t s, const std::string& what) {
  if (s < 0) throw std::runtime_error("HDF5: " + what);
}

// RAII for hid_t handles.
struct H {
  hid_t id;
  herr_t (*close)(hid_t);
  H(hid_t i, herr_t (*c)(hid_t), const std::string& what) : id(i), close(c) {
    if (id < 0) throw std::runtime_error("HDF5: " + what);
  }
  ~H() { close(id); }
  H(const H&) = delete;
  H& operator=(const H&) = delete;
};

inline void set_attr_string(hid_t obj, const std::string& name, const std::string& value);

// Attributes of any size. An attribute kept in its object's header (HDF5's
// default, "compact" storage) holds at most 64 kB, and a study's metadata
// JSON outgrows that at a few hundred runs. In "dense" storage (a fractal
// heap beside the header, HDF5 1.8 file format) an attribute's size has no
// such bound (HDF5 User's Guide, "Attribute storage"; a 50 MB one is
// written and read back by h5py here). Kept an attribute rather than made
// a dataset: the file's layout, and every reader of it, stay as they were.
// allow_large_attributes: on a file access list, the 1.8 format's object
// headers (which dense storage needs; HDF5 >= 1.8 and h5py read them).
inline void allow_large_attributes(hid_t fapl) {
  check(H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST), "file format bounds");
}

// A group whose attributes are in dense storage from the first: any text
// (JSON metadata, column lists) fits. Its file needs allow_large_attributes.
inline hid_t create_group_for_large_attributes(hid_t parent, const std::string& name) {
  H gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, "group properties");
  check(H5Pset_attr_phase_change(gcpl.id, 0, 0), "dense attribute storage");
  return H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, gcpl.id, H5P_DEFAULT);
}

// A dataset; with `units`, its attribute "units" (result.h5's datasets all
// carry one: mm, mm/s, 1/s, MPa, N, s, 1).
inline void write_array(hid_t parent, const std::string& name, const void* data, hid_t type, std::vector<hsize_t> dims,
                        const char* units = nullptr) {
  H space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose, "dataspace " + name);
  H set(H5Dcreate2(parent, name.c_str(), type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
        "create " + name);
  check(H5Dwrite(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + name);
  if (units) set_attr_string(set.id, "units", units);
}

inline void write_doubles(hid_t parent, const std::string& name, const std::vector<double>& v, hsize_t cols = 1,
                          const char* units = nullptr) {
  std::vector<hsize_t> dims{v.size() / cols};
  if (cols > 1) dims.push_back(cols);
  write_array(parent, name, v.data(), H5T_NATIVE_DOUBLE, dims, units);
}

inline void set_attr_string(hid_t obj, const std::string& name, const std::string& value) {
  if (H5Aexists(obj, name.c_str()) > 0) check(H5Adelete(obj, name.c_str()), "delete attribute " + name);
  H type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
  check(H5Tset_size(type.id, std::max<std::size_t>(value.size(), 1)), "string size");
  H space(H5Screate(H5S_SCALAR), H5Sclose, "scalar space");
  const std::string what = "attribute " + name + " (" + std::to_string(value.size()) + " bytes)";
  H attr(H5Acreate2(obj, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose, what);
  check(H5Awrite(attr.id, type.id, value.c_str()), "write " + what);
}

}  // namespace rpfem::h5
