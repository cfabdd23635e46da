// Reading a run's results back: history.csv columns and result.h5 datasets.
#pragma once
#include <map>
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

// A dataset of result.h5 as doubles (row-major), with its shape.
std::vector<double> read_h5_dataset(const std::string& h5_path, const std::string& dataset,
                                    std::vector<unsigned long long>* shape = nullptr);
// Step numbers recorded in result.h5 (groups under /steps).
std::vector<int> read_h5_steps(const std::string& h5_path);

}  // namespace rpfem
