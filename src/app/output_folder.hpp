// The output folder a command writes into (--out): created if missing. A
// name that cannot be one (empty, under a file, a file itself, too long,
// on a read-only or missing file system) is bad input, said so with the
// option and the system's reason, not an internal error.
#pragma once
#include <string>

namespace rpfem {

// Throws InputError naming `option` (e.g. "--out") and `dir`.
void make_output_folder(const std::string& dir, const std::string& option = "--out");

}  // namespace rpfem
