#include "io/variants.hpp"

#include <set>

namespace rpfem {

std::vector<Variant> read_variants(CaseSection root) {
  std::vector<Variant> out;
  std::set<std::string> names;
  for (CaseSection s : root.table_array("variants")) {
    Variant v;
    v.name = s.name("name", std::nullopt);
    if (v.name.empty() || v.name == "all" || v.name.find('/') != std::string::npos || !names.insert(v.name).second)
      s.fail("name", "a non-empty name, unique among the variants, not 'all', without '/'");
    v.set = s.text_array("set", "overrides \"key.path=value\", as --set");
    out.push_back(v);
  }
  return out;
}

const Variant& find_variant(const std::vector<Variant>& variants, const std::string& name, const std::string& file) {
  std::string known;
  for (const auto& v : variants) {
    if (v.name == name) return v;
    known += (known.empty() ? "" : ", ") + v.name;
  }
  throw InputError(file + ": --variant '" + name + "': no such variant; the case declares " +
                   (known.empty() ? std::string("none") : known + " (or 'all')"));
}

}  // namespace rpfem
