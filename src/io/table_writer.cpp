#include "io/table_writer.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "io/hdf5_handles.hpp"
#include "io/result_writer.hpp"

namespace rpfem {

using namespace h5;

void Table::add_row(const std::map<std::string, double>& n, const std::map<std::string, std::string>& s) {
  for (const auto& c : columns) {  // the whole row checked before any of it is added
    const auto it = n.find(c);
    if (it == n.end() && !s.count(c)) throw std::logic_error("table row without column '" + c + "'");
    if (it != n.end() && !std::isfinite(it->second)) throw std::logic_error("table column '" + c + "': non-finite value");
  }
  for (const auto& c : columns) {
    if (auto it = n.find(c); it != n.end())
      numbers[c].push_back(it->second);
    else
      texts[c].push_back(s.at(c));
  }
}

std::size_t Table::rows() const {
  if (columns.empty()) return 0;
  const auto it = numbers.find(columns.front());
  return it != numbers.end() ? it->second.size() : texts.at(columns.front()).size();
}

void write_table_csv(const std::string& path, const Table& t) {
  std::string out;
  for (std::size_t c = 0; c < t.columns.size(); ++c) out += (c ? "," : "") + t.columns[c];
  out += "\n";
  char buf[64];
  for (std::size_t r = 0; r < t.rows(); ++r) {
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      if (c) out += ",";
      const std::string& name = t.columns[c];
      if (auto it = t.numbers.find(name); it != t.numbers.end()) {
        std::snprintf(buf, sizeof buf, "%.10g", it->second[r]);
        out += buf;
      } else {
        out += t.texts.at(name)[r];  // names and keys: no commas or quotes
      }
    }
    out += "\n";
  }
  write_text_atomically(path, out);
}

void write_table_h5(const std::string& path, const Table& t, const std::string& metadata_json) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // /table's attributes (the metadata JSON, the column list) grow with the
  // study: dense attribute storage (io/hdf5_handles.hpp), no size bound.
  H access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
  allow_large_attributes(access.id);
  H file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id), H5Fclose, "create " + path);
  H g(create_group_for_large_attributes(file.id, "/table"), H5Gclose, "/table");
  std::string order;
  for (const auto& name : t.columns) {
    order += (order.empty() ? "" : ",") + name;
    if (auto it = t.numbers.find(name); it != t.numbers.end()) {
      write_doubles(g.id, name, it->second);
      continue;
    }
    const auto& v = t.texts.at(name);
    std::size_t width = 1;
    for (const auto& s : v) width = std::max(width, s.size() + 1);
    std::vector<char> buf(v.size() * width, '\0');
    for (std::size_t r = 0; r < v.size(); ++r) std::memcpy(&buf[r * width], v[r].data(), v[r].size());
    H type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    check(H5Tset_size(type.id, width), "string size");
    write_array(g.id, name, buf.data(), type.id, {v.size()});
  }
  set_attr_string(g.id, "columns", order);
  set_attr_string(g.id, "metadata", metadata_json);
}

}  // namespace rpfem
