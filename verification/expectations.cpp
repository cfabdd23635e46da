#include "expectations.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/variants.hpp"
#include "results.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

const NamedValues<MeasureKind> kMeasureKinds{{"load_difference", MeasureKind::LoadDifference},
                                             {"history_max", MeasureKind::HistoryMax},
                                             {"summary", MeasureKind::Summary}};
const NamedValues<ExpectedEnd> kOutcomes{{"finished", ExpectedEnd::Finished}, {"stopped", ExpectedEnd::Stopped}};

// A measure as read, with its reference run still unresolved.
struct ReadMeasure {
  ExpectedMeasure m;
  ExpectedRun reference;
};
struct ReadExpectation {
  Expectation e;
  std::vector<ReadMeasure> measures;
};

// The case's own formulation (run.formulation), so that a reference naming
// it is the same run as one that does not.
std::string own_formulation(const std::string& case_file) {
  try {
    return toml::parse_file(case_file)["run"]["formulation"].value_or(std::string("none"));
  } catch (const toml::parse_error&) {
    return "";
  }
}

// The checker reads [expect] without the rest of the case, so it checks
// the tables' keys itself (`rpfem run` also has CaseFile::finish).
void only_keys(const CaseSection& t, const std::vector<std::string>& known) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  for (const auto& k : t.keys())
    if (std::find(known.begin(), known.end(), k) == known.end())
      t.fail(k, "unknown key (misspelt?); expected one of " + list);
}

ReadExpectation read_expect(CaseSection t, const std::string& case_file) {
  only_keys(t, {"outcome", "reason_contains", "warnings", "measure"});
  ReadExpectation out;
  Expectation& e = out.e;
  e.outcome = t.choice("outcome", std::nullopt, kOutcomes);
  if (t.has("reason_contains")) {
    if (e.outcome != ExpectedEnd::Stopped) t.fail("reason_contains", "only with outcome = \"stopped\"");
    e.reason_contains = t.text_array("reason_contains", "words the stop reason must contain");
  }
  if (t.has("warnings")) e.warnings = t.text_array("warnings", "words of each warning the run must record");
  for (CaseSection s : t.table_array("measure")) {
    ReadMeasure r;
    ExpectedMeasure& m = r.m;
    m.what = s.choice("what", std::nullopt, kMeasureKinds);
    if (m.what == MeasureKind::LoadDifference)
      only_keys(s, {"what", "load", "reference_load", "from", "stroke_tolerance", "reference_case",
                    "reference_formulation", "reference_set", "min", "max"});
    else
      only_keys(s, {"what", m.what == MeasureKind::Summary ? "key" : "column", "min", "max"});
    if (m.what == MeasureKind::LoadDifference) {
      m.column = s.text("load", std::nullopt);
      m.reference_load = s.text("reference_load", m.column);
      m.from = s.real("from", 0.0, Range::nonnegative(), "mm of stroke");
      m.stroke_tolerance = s.real("stroke_tolerance", 0.0, Range::nonnegative(), "mm");
      const std::string ref = s.text("reference_case", "");
      const fs::path dir = fs::path(case_file).parent_path();
      r.reference.case_file = ref.empty() ? case_file : (dir / ref).lexically_normal().string();
      if (!fs::exists(r.reference.case_file)) s.fail("reference_case", "no such file: " + r.reference.case_file);
      r.reference.formulation = s.text("reference_formulation", "");
      if (!r.reference.formulation.empty() && r.reference.formulation == own_formulation(r.reference.case_file))
        r.reference.formulation.clear();
      if (s.has("reference_set")) r.reference.overrides = s.text_array("reference_set", "overrides \"key.path=value\"");
    } else {
      m.column = m.what == MeasureKind::Summary ? s.text("key", std::nullopt) : s.text("column", std::nullopt);
    }
    m.min = s.optional_real("min", Range::any());
    m.max = s.optional_real("max", Range::any());
    if (!m.min && !m.max) s.fail("max", "give the bounds of the measured value: min, max or both");
    if (m.min && m.max && *m.min > *m.max) s.fail("min", "min is above max");
    out.measures.push_back(r);
  }
  return out;
}

// Each [expect] table of the case with the run it describes.
std::vector<std::pair<ExpectedRun, ReadExpectation>> read_all(CaseSection root, const std::string& case_file) {
  std::vector<std::pair<ExpectedRun, ReadExpectation>> out;
  if (auto t = root.table("expect")) out.push_back({{"case", case_file, "", "", {}}, read_expect(*t, case_file)});
  for (CaseSection v : root.table_array("variants")) {
    auto t = v.table("expect");
    if (!t) continue;
    const std::string name = v.text("name", std::nullopt);
    if (name == "case" || name.rfind("reference-", 0) == 0)
      v.fail("name", "'case' and 'reference-N' name the checks' own runs");
    out.push_back({{name, case_file, name, "", {}}, read_expect(*t, case_file)});
  }
  return out;
}

bool contains(const std::string& text, const std::string& word) {
  auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  };
  return lower(text).find(lower(word)) != std::string::npos;
}

std::string describe(const ExpectedRun& r) {
  std::string s = r.label + " (" + fs::path(r.case_file).filename().string();
  if (!r.variant.empty()) s += " --variant " + r.variant;
  if (!r.formulation.empty()) s += " --formulation " + r.formulation;
  for (const auto& o : r.overrides) s += " --set " + o;
  return s + ")";
}

double largest_magnitude(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::isfinite(x) ? std::abs(x) : INFINITY);
  return m;
}

// The measured value of m on the run in dir.
double measure(const ExpectedCase& c, const ExpectedMeasure& m, const std::string& dir, const std::string& runs_dir) {
  if (m.what == MeasureKind::Summary) {
    const auto v = summary_number(dir, m.column);
    if (!v) throw std::runtime_error("summary.json has no number '" + m.column + "'");
    return *v;
  }
  const History a = read_history(dir + "/history.csv");
  if (m.what == MeasureKind::HistoryMax) return largest_magnitude(a.at(m.column));
  const std::string ref_dir = runs_dir + "/" + c.runs[m.reference].label;
  if (!run_finished(ref_dir))
    throw std::runtime_error("the reference run " + describe(c.runs[m.reference]) + " did not finish");
  const History b = read_history(ref_dir + "/history.csv");
  return load_difference(a, m.column, b, m.reference_load, m.from, m.stroke_tolerance);
}

std::string sci3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace

const std::string& measure_kind_name(MeasureKind what) { return name_of(kMeasureKinds, what); }
const std::string& outcome_name(ExpectedEnd outcome) { return name_of(kOutcomes, outcome); }

std::vector<std::string> ExpectedRun::arguments() const {
  std::vector<std::string> a{case_file, "--quiet"};
  if (!variant.empty()) a.insert(a.end(), {"--variant", variant});
  if (!formulation.empty()) a.insert(a.end(), {"--formulation", formulation});
  for (const auto& o : overrides) a.insert(a.end(), {"--set", o});
  return a;
}

void validate_expect_tables(CaseSection root, const std::string& case_file) { read_all(root, case_file); }

ExpectedCase read_expected_case(const std::string& case_file) {
  CaseFile file(case_file);
  const std::vector<Variant> variants = read_variants(file.root());
  // Two runs are the same when they run the same file, formulation and
  // overrides (a variant's counted as overrides): a reference that is
  // another expectation's run is run once.
  const auto overrides = [&](const ExpectedRun& r) {
    std::vector<std::string> o;
    if (!r.variant.empty()) o = find_variant(variants, r.variant, case_file).set;
    o.insert(o.end(), r.overrides.begin(), r.overrides.end());
    return o;
  };
  const auto same_run = [&](const ExpectedRun& a, const ExpectedRun& b) {
    return fs::weakly_canonical(a.case_file) == fs::weakly_canonical(b.case_file) &&
           a.formulation == b.formulation && overrides(a) == overrides(b);
  };
  ExpectedCase out;
  out.file = case_file;
  auto all = read_all(file.root(), case_file);
  for (const auto& [run, x] : all) out.runs.push_back(run);
  int references = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    Expectation e = all[i].second.e;
    e.run = static_cast<int>(i);
    for (const ReadMeasure& r : all[i].second.measures) {
      ExpectedMeasure m = r.m;
      if (m.what == MeasureKind::LoadDifference) {
        const auto it = std::find_if(out.runs.begin(), out.runs.end(),
                                     [&](const ExpectedRun& x) { return same_run(x, r.reference); });
        m.reference = static_cast<int>(it - out.runs.begin());
        if (it == out.runs.end()) {
          out.runs.push_back(r.reference);
          out.runs.back().label = "reference-" + std::to_string(++references);
        }
      }
      e.measures.push_back(m);
    }
    out.expectations.push_back(e);
  }
  if (out.expectations.empty()) throw InputError(case_file + ": no [expect] table, in the case or a variant");
  return out;
}

ExpectationResult evaluate_expectation(const ExpectedCase& c, const Expectation& e, const std::string& runs_dir) {
  ExpectationResult r;
  const ExpectedRun& run = c.runs[e.run];
  r.run = run.label;
  const std::string dir = runs_dir + "/" + run.label;
  std::vector<std::string> failed;
  const Summary summary(dir);
  const std::string status = summary.string("status").value_or("no summary.json");
  const std::string& expected = outcome_name(e.outcome);
  if (status != expected) failed.push_back("outcome " + status + ", expected " + expected);
  const std::string reason = summary.string("reason").value_or("");
  for (const auto& w : e.reason_contains)
    if (!contains(reason, w)) failed.push_back("the stop reason lacks '" + w + "': " + reason);
  const std::vector<std::string> warnings = summary.strings("warnings");
  for (const auto& w : e.warnings)
    if (std::none_of(warnings.begin(), warnings.end(), [&](const std::string& x) { return contains(x, w); }))
      failed.push_back("no warning contains '" + w + "'");
  for (const auto& x : warnings)
    if (std::none_of(e.warnings.begin(), e.warnings.end(), [&](const std::string& w) { return contains(x, w); }))
      failed.push_back("unexpected warning: " + x);
  std::vector<std::string> dirs{dir};
  for (const ExpectedMeasure& m : e.measures) {
    MeasuredValue v;
    v.name = measure_kind_name(m.what) + " " + m.column;
    if (m.reference >= 0) {
      v.name += " vs " + describe(c.runs[m.reference]);
      const std::string d = runs_dir + "/" + c.runs[m.reference].label;
      if (std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
    }
    try {
      v.value = measure(c, m, dir, runs_dir);
      v.pass = std::isfinite(v.value) && (!m.min || v.value >= *m.min) && (!m.max || v.value <= *m.max);
      if (!v.pass)
        failed.push_back(v.name + " = " + sci3(v.value) + ", expected in [" + (m.min ? sci3(*m.min) : "-inf") + ", " +
                         (m.max ? sci3(*m.max) : "inf") + "]");
    } catch (const std::exception& ex) {
      v.value = NAN;
      failed.push_back(v.name + ": " + ex.what());
    }
    r.values.push_back(v);
  }
  for (const auto& d : dirs)
    if (const std::string bad = non_finite_entries(d); !bad.empty()) failed.push_back(d + ": " + bad);
  r.pass = failed.empty();
  for (const auto& f : failed) r.message += (r.message.empty() ? "" : "; ") + f;
  if (r.pass) r.message = "as expected (" + expected + ")";
  return r;
}

std::string non_finite_entries(const std::string& run_dir) {
  std::string out;
  std::ifstream csv(run_dir + "/history.csv");
  std::string line, cell;
  std::getline(csv, line);
  for (int row = 1; std::getline(csv, line); ++row) {
    std::stringstream ls(line);
    while (std::getline(ls, cell, ',')) {
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0' || !std::isfinite(x))
        return "history.csv row " + std::to_string(row) + ": '" + cell + "'";
    }
  }
  // Outside strings, JSON's only words are true, false and null: any other
  // (nan, inf) is a non-finite number.
  const std::string s = read_text(run_dir + "/summary.json");
  if (s.empty()) return "no summary.json";
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '"') {
      for (++i; i < s.size() && s[i] != '"'; ++i) i += s[i] == '\\';
    } else if (std::isalpha(static_cast<unsigned char>(s[i])) && (i == 0 || !std::isalnum(s[i - 1]))) {
      std::size_t j = i;
      while (j < s.size() && std::isalpha(static_cast<unsigned char>(s[j]))) ++j;
      const std::string word = s.substr(i, j - i);
      if (word != "true" && word != "false" && word != "null" && word != "e" && word != "E")
        return "summary.json: '" + word + "' at offset " + std::to_string(i);
      i = j - 1;
    }
  }
  return out;
}

}  // namespace rpfem
