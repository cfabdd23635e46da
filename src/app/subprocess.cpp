#include "app/subprocess.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "core/types.hpp"

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

std::string capture_shell(const std::string& command_line, int* rc) {
  std::string out;
  FILE* p = popen((command_line + " 2>&1").c_str(), "r");
  if (!p) throw std::runtime_error("cannot run: " + command_line);
  std::array<char, 4096> buf;
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), p)) > 0;) out.append(buf.data(), n);
  const int status = pclose(p);
  if (rc) *rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

int report_errors(const std::function<int()>& command) {
  try {
    return command();
  } catch (const InputError& e) {
    std::fflush(stdout);  // what was said before the error comes first
    std::fprintf(stderr, "rpfem: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "rpfem: internal error: %s\n", e.what());
    return 1;
  }
}

}  // namespace rpfem
