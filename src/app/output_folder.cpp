#include "app/output_folder.hpp"

#include <filesystem>
#include <system_error>

#include "core/types.hpp"

namespace fs = std::filesystem;

namespace rpfem {

void make_output_folder(const std::string& dir, const std::string& option) {
  if (dir.empty()) throw InputError(option + ": expected a folder name, got an empty one");
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(option + " '" + dir + "': a file is there; expected a folder (or a name not yet used)");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(option + " '" + dir + "': cannot create the output folder: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw InputError(option + " '" + dir + "': not a folder after creating it");
}

}  // namespace rpfem
