// Reading a run's results back: history.csv columns and result.h5 datasets.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rpfem {

struct History {
  std::vector<std::string> columns;
  std::map<std::string, std::vector<double>> data;
  const std::vector<double>& at(const std::string& col) const;  // throws if absent
  std::size_t rows() const { return data.empty() ? 0 : data.begin()->second.size(); }
};
History read_history(const std::string& csv_path);

// The largest relative difference of |run[column]| from |ref[ref_column]|
// over the run's strokes from `from` mm (curve_comparison.hpp: the
// reference interpolated linearly, `stroke_tolerance` mm of shift allowed).
double load_difference(const History& run, const std::string& column, const History& ref,
                       const std::string& ref_column, double from, double stroke_tolerance);

// The largest jump of |run[column]| from `from` mm (curve_comparison.hpp).
double load_jump(const History& run, const std::string& column, double from);

// A whole text file ("" if unreadable).
std::string read_text(const std::string& path);
// Whether the run's summary.json says it finished.
bool run_finished(const std::string& run_dir);

// A run's summary.json, read once; a value by its key path (a top-level
// key, or keys joined by '.': "derived.reference_speed_mm_s"), or nothing
// if absent, of another type or unreadable.
class Summary {
 public:
  explicit Summary(const std::string& run_dir);
  bool exists() const { return !text_.empty(); }
  std::optional<std::string> string(const std::string& key) const;
  std::optional<double> number(const std::string& key) const;
  std::vector<std::string> strings(const std::string& key) const;  // an array of strings; empty if absent

 private:
  std::string text_;
};
// One value, reading the file for it.
std::optional<std::string> summary_string(const std::string& run_dir, const std::string& key);
std::optional<double> summary_number(const std::string& run_dir, const std::string& key);
// An array of strings (e.g. "warnings"); empty if absent.
std::vector<std::string> summary_strings(const std::string& run_dir, const std::string& key);

// A dataset of result.h5 as doubles (row-major), with its shape.
std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset,
                                    std::vector<unsigned long long>* shape = nullptr);
// A fixed-length string attribute of an object of an HDF5 file (result.h5's
// /metadata json, sweep.h5's /table metadata and columns).
std::string read_h5_text_attribute(const std::string& h5_path, const std::string& object, const std::string& name);
// Step numbers recorded in result.h5 (groups under /steps).
std::vector<int> read_h5_steps(const std::string& h5_path);

}  // namespace rpfem
