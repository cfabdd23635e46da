#include "app/case_folder.hpp"

#include <algorithm>

#include "core/types.hpp"

namespace fs = std::filesystem;

namespace rpfem {

std::vector<fs::path> case_files(const std::string& folder, const std::vector<std::string>& names,
                                 const std::string& what) {
  std::vector<fs::path> files;
  if (fs::is_directory(folder))
    for (const auto& e : fs::directory_iterator(folder))
      if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::string known;
  for (const auto& p : files) known += (known.empty() ? "" : ", ") + p.stem().string();
  for (const auto& s : names)
    if (std::none_of(files.begin(), files.end(), [&](const fs::path& p) { return p.stem().string() == s; }))
      throw InputError(folder + ": no " + what + " '" + s +
                       "'; expected one of: " + (known.empty() ? "(none)" : known));
  return files;
}

}  // namespace rpfem
