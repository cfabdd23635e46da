// Where the program's data lives: the folder holding cases/, reports/ and
// verification/checks.toml. An installed rpfem (cmake --install) finds
// PREFIX/share/rpfem next to its PREFIX/bin; one run from its build tree
// finds the source tree it was built from.
#pragma once
#include <string>

namespace rpfem {

std::string data_dir();

}  // namespace rpfem
