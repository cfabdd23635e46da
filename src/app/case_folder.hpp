// The case files of a folder (`rpfem suite`: the scenes of CASES, the
// studies of CASES/studies), by name.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace rpfem {

// The .toml files of `folder` (none if it does not exist), sorted; an
// InputError naming the folder and the files there if one of `names` (file
// names without .toml) is not among them: "FOLDER: no WHAT 'NAME'; expected
// one of: ...".
std::vector<std::filesystem::path> case_files(const std::string& folder, const std::vector<std::string>& names,
                                              const std::string& what);

}  // namespace rpfem
