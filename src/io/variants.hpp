// Case variants: named sets of overrides declared in the case file
//   [[variants]]
//   name = "m0.1"
//   set = ["dies.top_die.friction.m=0.1"]
// run by `rpfem run CASE --variant NAME` (or `all`: each into OUT/NAME).
#pragma once
#include <string>
#include <vector>

#include "io/case_file.hpp"

namespace rpfem {

struct Variant {
  std::string name;
  std::vector<std::string> set;  // "key.path=value", as --set
};

// Reads and validates [[variants]] (unique non-empty names, `set` an array
// of strings). Throws InputError.
std::vector<Variant> read_variants(CaseSection root);
// The named variant; InputError listing the known names if absent.
const Variant& find_variant(const std::vector<Variant>& variants, const std::string& name, const std::string& file);

}  // namespace rpfem
