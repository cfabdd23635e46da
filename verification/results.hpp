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

// A value of the run's summary.json by its key path (a top-level key, or
// keys joined by '.': "derived.reference_speed_mm_s"), or nothing if absent,
// of another type or unreadable.
std::optional<std::string> summary_string(const std::string& run_dir, const std::string& key);
std::optional<double> summary_number(const std::string& run_dir, const std::string& key);
// An array of strings (e.g. "warnings"); empty if absent.
std::vector<std::string> summary_strings(const std::string& run_dir, const std::string& key);

// A dataset of result.h5 as doubles (row-major), with its shape.
std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset,
                                    std::vector<unsigned long long>* shape = nullptr);
// Step numbers recorded in result.h5 (groups under /steps).
std::vector<int> read_h5_steps(const std::string& h5_path);

}  // namespace rpfem
