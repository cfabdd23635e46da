// A number in messages (warnings, stop reasons): two significant digits,
// printf's %.2g.
#pragma once
#include <cstdio>
#include <string>

namespace rpfem {

inline std::string sci(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

}  // namespace rpfem
