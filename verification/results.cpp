#include "results.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rpfem {

const std::vector<double>& History::at(const std::string& col) const {
  auto it = data.find(col);
  if (it == data.end()) throw std::runtime_error("history.csv has no column '" + col + "'");
  return it->second;
}

namespace {

// The text after "key": in summary.json, or npos.
std::size_t summary_value_at(const std::string& text, const std::string& key) {
  const auto k = text.find("\"" + key + "\"");
  if (k == std::string::npos) return k;
  const auto colon = text.find(':', k);
  return colon == std::string::npos ? colon : text.find_first_not_of(" \t\n", colon + 1);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::optional<std::string> summary_string(const std::string& run_dir, const std::string& key) {
  const std::string s = read_text(run_dir + "/summary.json");
  const auto v = summary_value_at(s, key);
  if (v == std::string::npos || s[v] != '"') return std::nullopt;
  std::string out;
  for (std::size_t i = v + 1; i < s.size() && s[i] != '"'; ++i) out += s[i] == '\\' && i + 1 < s.size() ? s[++i] : s[i];
  return out;
}

std::optional<double> summary_number(const std::string& run_dir, const std::string& key) {
  const std::string s = read_text(run_dir + "/summary.json");
  const auto v = summary_value_at(s, key);
  if (v == std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(s.c_str() + v, &end);
  return end == s.c_str() + v ? std::nullopt : std::optional<double>(x);
}

History read_history(const std::string& csv_path) {
  std::ifstream in(csv_path);
  if (!in) throw std::runtime_error("cannot open " + csv_path);
  History h;
  std::string line, cell;
  std::getline(in, line);
  std::stringstream hs(line);
  while (std::getline(hs, cell, ',')) h.columns.push_back(cell);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ls(line);
    for (const auto& c : h.columns) {
      if (!std::getline(ls, cell, ',')) throw std::runtime_error(csv_path + ": short row");
      h.data[c].push_back(std::stod(cell));
    }
  }
  return h;
}

namespace {
struct H5File {
  hid_t id;
  explicit H5File(const std::string& p) : id(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {
    if (id < 0) throw std::runtime_error("cannot open " + p);
  }
  ~H5File() { H5Fclose(id); }
};
}  // namespace

std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset,
                                    std::vector<unsigned long long>* shape) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5File f(h5_path);
  const hid_t d = H5Dopen2(f.id, dataset.c_str(), H5P_DEFAULT);
  if (d < 0) throw std::runtime_error(h5_path + ": no dataset " + dataset);
  const hid_t s = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(s);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  H5Sget_simple_extent_dims(s, dims.data(), nullptr);
  std::size_t n = 1;
  for (auto x : dims) n *= x;
  std::vector<double> out(n);
  const herr_t st = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(s);
  H5Dclose(d);
  if (st < 0) throw std::runtime_error(h5_path + ": cannot read " + dataset);
  if (shape) shape->assign(dims.begin(), dims.end());
  return out;
}

std::vector<int> read_h5_steps(const std::string& h5_path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5File f(h5_path);
  const hid_t g = H5Gopen2(f.id, "/steps", H5P_DEFAULT);
  if (g < 0) throw std::runtime_error(h5_path + ": no /steps group");
  std::vector<int> steps;
  H5Literate(
      g, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        const std::string s(name);
        if (!s.empty() && std::all_of(s.begin(), s.end(), ::isdigit))
          static_cast<std::vector<int>*>(data)->push_back(std::stoi(s));
        return 0;
      },
      &steps);
  H5Gclose(g);
  std::sort(steps.begin(), steps.end());
  return steps;
}

}  // namespace rpfem
