#include "app/subprocess.hpp"

#include <cstdlib>
#include <filesystem>
#include <sys/wait.h>

namespace rpfem {

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string self_executable() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

int run_shell(const std::string& command_line) {
  const int status = std::system(command_line.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace rpfem
