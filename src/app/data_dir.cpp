#include "app/data_dir.hpp"

#include <filesystem>
#include <system_error>

namespace rpfem {

std::string data_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  // The executable's own path (Linux), then ../share/rpfem from its folder.
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "rpfem";
    if (fs::is_directory(installed / "cases", ec)) return installed.string();
  }
  return RPFEM_SOURCE_DIR;
}

}  // namespace rpfem
