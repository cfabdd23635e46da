// A table with one row per run (a parameter sweep): numeric and text
// columns in a fixed order, written as CSV (header line, %.10g numbers) and
// as HDF5 (one 1-D dataset per column under /table, texts as fixed-length
// strings, the column order as the attribute /table/columns and a JSON
// text as /table/metadata). A value that was not measured is -1 in both
// (every measured quantity of a sweep is >= 0); a non-finite number is a
// programming error (std::logic_error, nothing written).
#pragma once
#include <map>
#include <string>
#include <vector>

namespace rpfem {

struct Table {
  std::vector<std::string> columns;  // in order
  std::map<std::string, std::vector<double>> numbers;
  std::map<std::string, std::vector<std::string>> texts;
  void add_row(const std::map<std::string, double>& numbers, const std::map<std::string, std::string>& texts);
  std::size_t rows() const;
};

void write_table_csv(const std::string& path, const Table& t);
void write_table_h5(const std::string& path, const Table& t, const std::string& metadata_json);

}  // namespace rpfem
