#include "results.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "curve_comparison.hpp"

namespace rpfem {

const std::vector<double>& History::at(const std::string& col) const {
  auto it = data.find(col);
  if (it == data.end()) throw std::runtime_error("history.csv has no column '" + col + "'");
  return it->second;
}

namespace {

// In the JSON object opening at text[open], the position of the value of
// its member `key` (not of a nested object's), or npos.
std::size_t member_value_at(const std::string& text, std::size_t open, const std::string& key) {
  int depth = 0;
  for (std::size_t i = open; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      std::string name;
      for (++i; i < text.size() && text[i] != '"'; ++i) name += text[i] == '\\' && i + 1 < text.size() ? text[++i] : text[i];
      const std::size_t after = text.find_first_not_of(" \t\n", i + 1);
      if (depth == 1 && name == key && after != std::string::npos && text[after] == ':')
        return text.find_first_not_of(" \t\n", after + 1);
    } else if (c == '{' || c == '[') {
      ++depth;
    } else if ((c == '}' || c == ']') && --depth == 0) {
      return std::string::npos;
    }
  }
  return std::string::npos;
}

// The position of the value at `path` (keys joined by '.') in summary.json's
// text, or npos.
std::size_t summary_value_at(const std::string& text, const std::string& path) {
  std::size_t pos = text.find('{');
  for (std::size_t a = 0, b; pos != std::string::npos && a <= path.size(); a = b + 1) {
    b = path.find('.', a);
    if (b == std::string::npos) b = path.size();
    if (text[pos] != '{') return std::string::npos;
    pos = member_value_at(text, pos, path.substr(a, b - a));
  }
  return pos;
}

// The JSON string starting at text[at] ('"'), unescaped.
std::string json_string(const std::string& text, std::size_t& at) {
  std::string out;
  for (++at; at < text.size() && text[at] != '"'; ++at) out += text[at] == '\\' && at + 1 < text.size() ? text[++at] : text[at];
  return out;
}

std::vector<double> magnitudes(std::vector<double> v) {
  for (double& x : v) x = std::abs(x);
  return v;
}

}  // namespace

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool run_finished(const std::string& run_dir) { return summary_string(run_dir, "status").value_or("") == "finished"; }

double load_difference(const History& run, const std::string& column, const History& ref,
                       const std::string& ref_column, double from, double stroke_tolerance) {
  return curve_difference(run.at("stroke"), magnitudes(run.at(column)), ref.at("stroke"), magnitudes(ref.at(ref_column)),
                          from, stroke_tolerance)
      .worst;
}

double load_jump(const History& run, const std::string& column, double from) {
  return curve_jump(run.at("stroke"), magnitudes(run.at(column)), from).worst;
}

Summary::Summary(const std::string& run_dir) : text_(read_text(run_dir + "/summary.json")) {}

std::optional<std::string> Summary::string(const std::string& key) const {
  auto v = summary_value_at(text_, key);
  if (v == std::string::npos || text_[v] != '"') return std::nullopt;
  return json_string(text_, v);
}

std::vector<std::string> Summary::strings(const std::string& key) const {
  std::vector<std::string> out;
  auto v = summary_value_at(text_, key);
  if (v == std::string::npos || text_[v] != '[') return out;
  for (++v; v < text_.size() && text_[v] != ']'; ++v)
    if (text_[v] == '"') out.push_back(json_string(text_, v));
  return out;
}

std::optional<double> Summary::number(const std::string& key) const {
  const auto v = summary_value_at(text_, key);
  if (v == std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(text_.c_str() + v, &end);
  return end == text_.c_str() + v ? std::nullopt : std::optional<double>(x);
}

std::optional<std::string> summary_string(const std::string& run_dir, const std::string& key) {
  return Summary(run_dir).string(key);
}

std::vector<std::string> summary_strings(const std::string& run_dir, const std::string& key) {
  return Summary(run_dir).strings(key);
}

std::optional<double> summary_number(const std::string& run_dir, const std::string& key) {
  return Summary(run_dir).number(key);
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

std::string read_h5_text_attribute(const std::string& h5_path, const std::string& object, const std::string& name) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5File f(h5_path);
  const hid_t a = H5Aopen_by_name(f.id, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) throw std::runtime_error(h5_path + ": no attribute " + name + " on " + object);
  const hid_t t = H5Aget_type(a);
  std::string out(H5Tget_size(t), '\0');
  const herr_t st = H5Aread(a, t, out.data());
  H5Tclose(t);
  H5Aclose(a);
  if (st < 0) throw std::runtime_error(h5_path + ": cannot read attribute " + name + " on " + object);
  out.resize(std::min(out.size(), out.find('\0')));
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
