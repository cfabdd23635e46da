// Reading a TOML case file with validation and a record of every value used.
//
// Every read names its key, its default (if any) and what it expects; a value
// of the wrong type or out of range is an InputError naming the file, the
// full key path and the expectation. Keys never read are reported by finish()
// as unknown. used_json() returns every value actually used, defaults
// included, as JSON for the run's summary.
#pragma once
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "core/types.hpp"

namespace rpfem {

class CaseFile;

// Allowed range of a number: lo/hi bounds, open or closed.
struct Range {
  double lo = -INFINITY, hi = INFINITY;
  bool lo_open = false, hi_open = false;
  std::string describe() const;
  static Range positive() { return {0, INFINITY, true, false}; }
  static Range nonnegative() { return {0, INFINITY, false, false}; }
  static Range any() { return {}; }
};

class CaseSection {
 public:
  const std::string& path() const { return path_; }
  bool has(const std::string& key) const;
  // Numbers: required when def is empty.
  double real(const std::string& key, std::optional<double> def, Range r, const std::string& unit = "");
  std::optional<double> optional_real(const std::string& key, Range r, const std::string& unit = "");
  int integer(const std::string& key, std::optional<int> def, int lo, int hi);
  std::string text(const std::string& key, std::optional<std::string> def,
                   const std::vector<std::string>& allowed = {});
  // A text that names one of a fixed set of values (NamedValues, below):
  // read and checked as text() with those names allowed, returned as the
  // value it names. def: the default's name.
  template <class E>
  E choice(const std::string& key, std::optional<std::string> def, const std::vector<std::pair<std::string, E>>& names);
  bool flag(const std::string& key, std::optional<bool> def);
  // A name that becomes a column of history.csv, an HDF5 attribute or a
  // file name (a run, body, die, monitor, velocity group or variant):
  // letters, digits, '_', '-', '.' and '+', read as text(). check_name: a
  // name given as this table's key `key` (bodies.NAME, dies.NAME).
  std::string name(const std::string& key, std::optional<std::string> def);
  void check_name(const std::string& key) const;
  // Required arrays: of exactly n numbers (n < 0: any length >= 1), of strings.
  std::vector<double> real_array(const std::string& key, int n, const std::string& what);
  std::vector<std::string> text_array(const std::string& key, const std::string& what);
  // Sub-tables and arrays of tables.
  std::optional<CaseSection> table(const std::string& key);
  CaseSection required_table(const std::string& key);
  // The table, or an empty one if absent (so its defaults are recorded).
  CaseSection section(const std::string& key);
  std::vector<CaseSection> table_array(const std::string& key);
  std::vector<std::string> keys() const;
  // Marks a subtree as known without reading it (another formulation's
  // settings when this run uses a different one).
  void ignore(const std::string& key);
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

 private:
  friend class CaseFile;
  // A required key that is absent: a misspelling of it among this table's
  // unread keys is named first ("unknown key ...; did you mean ...").
  [[noreturn]] void missing(const std::string& key, const std::string& expected) const;
  CaseSection(CaseFile* f, toml::table* t, std::string path) : file_(f), t_(t), path_(std::move(path)) {}
  // The key's whole path; "" names this table itself.
  std::string full(const std::string& key) const {
    return path_.empty() ? key : key.empty() ? path_ : path_ + "." + key;
  }
  toml::node* get(const std::string& key) const;
  void record(const std::string& key, toml::node&& value);

  CaseFile* file_;
  toml::table* t_;
  std::string path_;
};

class CaseFile {
 public:
  // Parses the file and applies overrides "a.b.c=value" (value in TOML
  // syntax; a bare word is taken as a string). Throws InputError.
  CaseFile(const std::string& path, const std::vector<std::string>& overrides = {});
  CaseSection root() { return CaseSection(this, &data_, ""); }
  const std::string& path() const { return path_; }
  // Throws InputError naming the first key that no reader used.
  void finish() const;
  std::string used_json() const;
  const toml::table& used() const { return used_; }
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;

 private:
  friend class CaseSection;
  std::string path_;
  toml::table data_;
  toml::table used_;
  std::set<std::string> visited_;
};

// The spellings of an enum's values in input files, in the order error
// messages list them: parsed once by CaseSection::choice, written back by
// name_of.
template <class E>
using NamedValues = std::vector<std::pair<std::string, E>>;

template <class E>
E CaseSection::choice(const std::string& key, std::optional<std::string> def, const NamedValues<E>& names) {
  std::vector<std::string> allowed;
  for (const auto& [name, value] : names) allowed.push_back(name);
  const std::string t = text(key, std::move(def), allowed);
  for (const auto& [name, value] : names)
    if (name == t) return value;
  throw std::logic_error(full(key) + ": the default '" + t + "' is none of the names");
}

template <class E>
const std::string& name_of(const NamedValues<E>& names, E value) {
  for (const auto& n : names)
    if (n.second == value) return n.first;
  return names.front().first;  // unreachable: every value has its name
}

// The shortest decimal text that reads back as v: an override's value
// (--set key=TEXT; a whole number reads as an integer, which a real key
// accepts too) and numbers shown to the user.
std::string exact_text(double v);

}  // namespace rpfem
