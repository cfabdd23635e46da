// Launching runs of this executable as child processes through the shell
// (`rpfem suite`, `rpfem calibrate`): quoting, the executable's own path,
// and the child's exit code.
#pragma once
#include <string>

namespace rpfem {

// s in single quotes, any ' inside escaped: one shell word.
std::string shell_quote(const std::string& s);
// This executable's path (/proc/self/exe).
std::string self_executable();
// Runs a shell command line; its exit code, -1 if it did not exit normally.
int run_shell(const std::string& command_line);
// Runs a shell command line; its standard output and error, its exit code
// in *rc (-1 if it did not exit normally).
std::string capture_shell(const std::string& command_line, int* rc = nullptr);

}  // namespace rpfem
