// Writes text to a file in the temporary directory; returns its path.
#pragma once
#include <filesystem>
#include <fstream>
#include <string>

namespace rpfem::unit {
inline std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / name;
  std::ofstream(p) << text;
  return p.string();
}
}  // namespace rpfem::unit
