// Runs of this executable as child processes through the shell (the
// Slurm engine's commands): quoting, the executable's own path, and the
// child's exit code; and the exit code of a command as `rpfem` reports it.
#pragma once
#include <functional>
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

// A command's exit code as `rpfem` reports it: its return; bad input
// (InputError) "rpfem: error: ..." on standard error and 2; any other
// exception "rpfem: internal error: ..." and 1.
int report_errors(const std::function<int()>& command);

}  // namespace rpfem
