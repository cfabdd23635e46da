#include <cctype>
#include "io/case_file.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <sstream>

#include "io/spelling.hpp"

namespace rpfem {

namespace {

std::string show(const toml::node& n) {
  std::ostringstream os;
  if (n.is_string()) os << '"' << n.as_string()->get() << '"';
  else if (n.is_table()) os << "a table";
  else if (n.is_array()) os << "an array";
  else n.visit([&](auto&& v) { os << v; });
  return os.str();
}

// An array index in a key path: its value, or SIZE_MAX where the part is
// not a number or does not fit (then no array has it).
std::size_t array_index(const std::string& s) {
  std::size_t v = SIZE_MAX;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return s.empty() || ec != std::errc() || end != s.data() + s.size() ? SIZE_MAX : v;
}

std::vector<std::string> split_path(const std::string& p) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : p) {
    if (c == '.') { out.push_back(cur); cur.clear(); }
    else cur += c;
  }
  out.push_back(cur);
  return out;
}

}  // namespace

std::string Range::describe() const {
  std::ostringstream os;
  if (lo == 0 && lo_open && std::isinf(hi)) return "a positive number";
  if (lo == 0 && !lo_open && std::isinf(hi)) return "a non-negative number";
  if (std::isinf(lo) && std::isinf(hi)) return "a number";
  os << "a number in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  return os.str();
}

// ---------------------------------------------------------------- CaseFile

CaseFile::CaseFile(const std::string& path, const std::vector<std::string>& overrides) : path_(path) {
  // The error-code forms: a path the system cannot look up (a name longer
  // than the file system allows, a component that is a file) is bad input,
  // not a filesystem_error.
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw InputError(path + ": cannot read the case file: " + ec.message() + "; expected the path of a readable TOML file" +
                     (ec == std::errc::filename_too_long ? " (a file name has at most 255 bytes on most file systems)" : ""));
  if (!std::filesystem::exists(st)) throw InputError(path + ": no such case file");
  if (std::filesystem::is_directory(st))
    throw InputError(path + ": a folder; expected a case file (TOML), e.g. one of the .toml files in it");
  try {
    data_ = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << path << ":" << e.source().begin.line << ":" << e.source().begin.column
       << ": malformed TOML: " << e.description();
    throw InputError(os.str());
  }
  for (const auto& o : overrides) {
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--set '" + o + "': expected key.path=value");
    const std::string key = o.substr(0, eq), text = o.substr(eq + 1);
    toml::table holder;
    try {
      holder = toml::parse("v = " + text);
    } catch (const toml::parse_error&) {
      holder.insert_or_assign("v", text);  // a bare word: a string
    }
    const auto parts = split_path(key);
    toml::node* cur = &data_;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      if (auto* t = cur->as_table()) {
        if (!t->contains(parts[i])) t->insert(parts[i], toml::table{});
        cur = t->get(parts[i]);
      } else if (auto* a = cur->as_array(); a && array_index(parts[i]) < a->size()) {
        cur = a->get(array_index(parts[i]));
      } else {
        throw InputError("--set '" + o + "': '" + parts[i] + "' does not name a table in " + path_);
      }
    }
    if (auto* t = cur->as_table()) t->insert_or_assign(parts.back(), *holder.get("v"));
    else throw InputError("--set '" + o + "': the parent of '" + parts.back() + "' is not a table in " + path_);
  }
}

void CaseFile::fail(const std::string& key, const std::string& expected) const {
  throw InputError(path_ + ": key '" + key + "': " + expected);
}

void CaseFile::finish() const {
  std::function<void(const toml::node&, const std::string&)> walk = [&](const toml::node& n, const std::string& p) {
    if (visited_.count(p)) return;
    if (auto* t = n.as_table()) {
      for (auto&& [k, v] : *t) walk(v, p.empty() ? std::string(k.str()) : p + "." + std::string(k.str()));
      return;
    }
    if (auto* a = n.as_array(); a && a->is_array_of_tables()) {
      for (std::size_t i = 0; i < a->size(); ++i) walk(*a->get(i), p + "." + std::to_string(i));
      return;
    }
    // The keys read beside it: a misspelling of one of them is named.
    const std::size_t dot = p.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : p.substr(0, dot + 1);
    std::vector<std::string> siblings;
    for (const auto& v : visited_)
      if (v.size() > parent.size() && v.compare(0, parent.size(), parent) == 0)
        siblings.push_back(v.substr(parent.size(), v.find('.', parent.size()) - parent.size()));
    const std::string near = nearest_spelling(p.substr(parent.size()), siblings);
    throw InputError(path_ + ": unknown key '" + p + "' (misspelt, or not used by this scene and formulation)" +
                     (near.empty() ? "" : "; did you mean '" + near + "'?"));
  };
  walk(data_, "");
}

std::string CaseFile::used_json() const {
  std::ostringstream os;
  os << toml::json_formatter{used_};
  return os.str();
}

// ------------------------------------------------------------- CaseSection

toml::node* CaseSection::get(const std::string& key) const { return t_->get(key); }

void CaseSection::record(const std::string& key, toml::node&& value) {
  file_->visited_.insert(full(key));
  toml::table* cur = &file_->used_;
  for (const auto& part : split_path(path_)) {
    if (part.empty()) continue;
    if (!cur->contains(part)) cur->insert(part, toml::table{});
    cur = cur->get(part)->as_table();
  }
  value.visit([&](auto&& v) { cur->insert_or_assign(key, v); });
}

void CaseSection::fail(const std::string& key, const std::string& expected) const {
  file_->fail(full(key), expected);
}

void CaseSection::missing(const std::string& key, const std::string& expected) const {
  // A key of this table that no reader took and that is a near spelling
  // of the one missing: the misspelling is the error.
  std::vector<std::string> unread;
  for (const auto& k : keys())
    if (!file_->visited_.count(full(k))) unread.push_back(k);
  for (const auto& k : unread)
    if (nearest_spelling(k, {key}) == key)
      throw InputError(file_->path_ + ": unknown key '" + full(k) + "' (misspelt?); did you mean '" + key + "'? ('" +
                       full(key) + "' is required)");
  fail(key, "required, expected " + expected);
}

bool CaseSection::has(const std::string& key) const { return t_->contains(key); }

void CaseSection::ignore(const std::string& key) {
  if (has(key)) file_->visited_.insert(full(key));
}

std::vector<std::string> CaseSection::keys() const {
  std::vector<std::string> k;
  for (auto&& [name, v] : *t_) k.emplace_back(name.str());
  return k;
}

std::optional<double> CaseSection::optional_real(const std::string& key, Range r, const std::string& unit) {
  auto* n = get(key);
  if (!n) return std::nullopt;
  const std::string expect = r.describe() + (unit.empty() ? "" : " (" + unit + ")");
  auto v = n->is_number() ? n->value<double>() : std::nullopt;
  if (!v) fail(key, "expected " + expect + ", got " + show(*n));
  const double x = *v;
  const bool ok = std::isfinite(x) && (r.lo_open ? x > r.lo : x >= r.lo) && (r.hi_open ? x < r.hi : x <= r.hi);
  if (!ok) fail(key, "expected " + expect + ", got " + show(*n));
  record(key, toml::value<double>(x));
  return x;
}

double CaseSection::real(const std::string& key, std::optional<double> def, Range r, const std::string& unit) {
  if (auto v = optional_real(key, r, unit)) return *v;
  if (!def) missing(key, r.describe() + (unit.empty() ? "" : " (" + unit + ")"));
  record(key, toml::value<double>(*def));
  return *def;
}

std::vector<double> CaseSection::real_array(const std::string& key, int n, const std::string& what) {
  const std::string expect =
      "an array of " + (n < 0 ? std::string("numbers") : std::to_string(n) + " numbers") + ": " + what;
  auto* a = get(key) ? get(key)->as_array() : nullptr;
  if (!a) missing(key, expect);
  std::vector<double> v;
  for (auto& e : *a) {
    auto d = e.value<double>();
    if (!d || !std::isfinite(*d)) fail(key, "expected " + expect + ", got " + show(*get(key)));
    v.push_back(*d);
  }
  if ((n >= 0 && static_cast<int>(v.size()) != n) || v.empty())
    fail(key, "expected " + expect + ", got " + show(*get(key)));
  record(key, toml::array(*a));
  return v;
}

std::vector<std::string> CaseSection::text_array(const std::string& key, const std::string& what) {
  const std::string expect = "an array of strings: " + what;
  auto* a = get(key) ? get(key)->as_array() : nullptr;
  if (!a) missing(key, expect);
  std::vector<std::string> v;
  for (auto& e : *a) {
    auto t = e.value<std::string>();
    if (!t) fail(key, "expected " + expect + ", got " + show(*get(key)));
    v.push_back(*t);
  }
  record(key, toml::array(*a));
  return v;
}

int CaseSection::integer(const std::string& key, std::optional<int> def, int lo, int hi) {
  const std::string expect = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  auto* n = get(key);
  if (!n) {
    if (!def) missing(key, expect);
    record(key, toml::value<int64_t>(*def));
    return *def;
  }
  auto v = n->is_integer() ? n->value<int64_t>() : std::nullopt;
  if (!v || *v < lo || *v > hi) fail(key, "expected " + expect + ", got " + show(*n));
  record(key, toml::value<int64_t>(*v));
  return static_cast<int>(*v);
}

namespace {
constexpr const char* kNameRule = "a name of letters, digits, '_', '-', '.' and '+' (it becomes a column, an attribute "
                                  "and a file name)";
bool valid_name(const std::string& v) {
  if (v.empty()) return false;
  for (unsigned char c : v)
    if (!(std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == '+')) return false;
  return true;
}
}  // namespace

std::string CaseSection::name(const std::string& key, std::optional<std::string> def) {
  const std::string v = text(key, std::move(def));
  if (!valid_name(v)) fail(key, std::string("expected ") + kNameRule + ", got \"" + v + "\"");
  return v;
}

void CaseSection::check_name(const std::string& key) const {
  if (!valid_name(key)) fail(key, std::string("the table's name: expected ") + kNameRule);
}

std::string CaseSection::text(const std::string& key, std::optional<std::string> def,
                              const std::vector<std::string>& allowed) {
  std::string expect = "a string";
  if (!allowed.empty()) {
    expect = "one of";
    for (const auto& a : allowed) expect += " '" + a + "'";
  }
  auto* n = get(key);
  std::string v;
  if (!n) {
    if (!def) missing(key, expect);
    v = *def;
  } else {
    if (!n->is_string()) fail(key, "expected " + expect + ", got " + show(*n));
    v = n->as_string()->get();
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), v) == allowed.end())
      fail(key, "expected " + expect + ", got " + show(*n));
  }
  record(key, toml::value<std::string>(v));
  return v;
}

bool CaseSection::flag(const std::string& key, std::optional<bool> def) {
  auto* n = get(key);
  bool v;
  if (!n) {
    if (!def) missing(key, "true or false");
    v = *def;
  } else {
    if (!n->is_boolean()) fail(key, "expected true or false, got " + show(*n));
    v = n->as_boolean()->get();
  }
  record(key, toml::value<bool>(v));
  return v;
}

std::optional<CaseSection> CaseSection::table(const std::string& key) {
  auto* n = get(key);
  if (!n) return std::nullopt;
  if (!n->is_table()) fail(key, "expected a table, got " + show(*n));
  return CaseSection(file_, n->as_table(), full(key));
}

CaseSection CaseSection::required_table(const std::string& key) {
  auto t = table(key);
  if (!t) missing(key, "a table");
  return *t;
}

CaseSection CaseSection::section(const std::string& key) {
  if (!has(key)) t_->insert(key, toml::table{});
  return required_table(key);
}

std::vector<CaseSection> CaseSection::table_array(const std::string& key) {
  std::vector<CaseSection> out;
  auto* n = get(key);
  if (!n) return out;
  if (auto* t = n->as_table()) {  // a single table is accepted as one entry
    out.push_back(CaseSection(file_, t, full(key)));
    return out;
  }
  auto* a = n->as_array();
  if (!a || !a->is_array_of_tables()) fail(key, "expected an array of tables ([[" + full(key) + "]])");
  for (std::size_t i = 0; i < a->size(); ++i)
    out.push_back(CaseSection(file_, a->get(i)->as_table(), full(key) + "." + std::to_string(i)));
  return out;
}

std::string exact_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace rpfem
