#include "app/study.hpp"

#include <algorithm>
#include <filesystem>

#include "core/types.hpp"
#include "factory.hpp"
#include "io/case_file.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

std::vector<std::string> optional_texts(CaseSection& s, const std::string& key, const std::string& what) {
  return s.has(key) ? s.text_array(key, what) : std::vector<std::string>{};
}

const NamedValues<StudyReference> kReferences{{"none", StudyReference::None},
                                              {"formulation", StudyReference::Formulation},
                                              {"richardson", StudyReference::Richardson},
                                              {"exact", StudyReference::Exact}};
const NamedValues<LoadMeasure> kMeasures{
    {"final", LoadMeasure::Final}, {"mean", LoadMeasure::Mean}, {"max_relative", LoadMeasure::MaxRelative}};
// Against Richardson's estimate only a load at one stroke or a mean.
const NamedValues<LoadMeasure> kEstimatedMeasures{{"final", LoadMeasure::Final}, {"mean", LoadMeasure::Mean}};

void check_formulation(const CaseSection& s, const std::string& key, const std::string& name) {
  if (!find_formulation(name)) s.fail(key, "a formulation (" + formulation_names() + "), got '" + name + "'");
}

bool has_axis(const Study& st, const std::string& key) {
  return std::any_of(st.axes.begin(), st.axes.end(), [&](const StudyAxis& a) { return a.key == key; });
}

// [study] case: a scene of the cases folder, or a file next to the study.
std::string read_case_path(CaseSection& s, const std::string& path, const std::string& cases_dir) {
  const std::string c = s.text("case", std::nullopt);
  const std::string file = c.size() > 5 && c.substr(c.size() - 5) == ".toml"
                               ? (fs::path(path).parent_path() / c).lexically_normal().string()
                               : cases_dir + "/" + c + ".toml";
  if (!fs::is_regular_file(file)) s.fail("case", "a scene of " + cases_dir + " or a case file, got '" + c + "'");
  return file;
}

// One [[study.axis]]: its key and values (the quick ones under quick).
StudyAxis read_axis(CaseSection& a, bool quick) {
  StudyAxis ax;
  ax.key = a.text("key", std::nullopt);
  const bool has_quick = a.has("quick");
  if (ax.formulation()) {
    auto v = a.text_array("values", "formulation names");
    const auto q = has_quick ? a.text_array("quick", "formulation names under --quick") : v;
    ax.values = quick ? q : v;
    for (const auto& f : ax.values) check_formulation(a, "values", f);
  } else {
    ax.values_full = a.real_array("values", -1, "the values of " + ax.key);
    ax.values_quick =
        has_quick ? a.real_array("quick", -1, "the values of " + ax.key + " under --quick") : ax.values_full;
    ax.numbers = quick ? ax.values_quick : ax.values_full;
    for (double x : ax.numbers) ax.values.push_back(exact_text(x));
  }
  return ax;
}

// [study.reference], after the axes (Richardson's axis is one of them).
void read_reference(CaseSection r, Study& st) {
  st.reference = r.choice("kind", std::string("none"), kReferences);
  st.from = r.real("from", 0.0, Range::nonnegative(), "mm");
  if (st.reference == StudyReference::Formulation) {
    st.reference_formulation = r.text("formulation", std::nullopt);
    check_formulation(r, "formulation", st.reference_formulation);
    st.reference_set = optional_texts(r, "set", "overrides of the reference run");
    st.measure = r.choice("measure", std::string("final"), kMeasures);
  } else if (st.reference == StudyReference::Exact) {
    st.exact_solution = r.text("solution", std::nullopt, {"upsetting_axisymmetric"});
    st.exact_diameter = r.real("diameter", std::nullopt, Range::positive(), "mm");
    st.exact_height = r.real("height", std::nullopt, Range::positive(), "mm");
    st.exact_height_per_stroke = r.real("height_per_stroke", 2.0, Range::positive());
    st.exact_body = r.text("body", std::string());
    st.measure = r.choice("measure", std::string("final"), kMeasures);
  } else if (st.reference == StudyReference::Richardson) {
    st.richardson_axis = r.text("axis", std::nullopt);
    if (!has_axis(st, st.richardson_axis)) r.fail("axis", "the key of one of the study's axes");
    st.measure = r.choice("measure", std::string("final"), kEstimatedMeasures);
    st.reference_formulation = r.text("formulation", std::string());
    if (!st.reference_formulation.empty()) {
      const auto f = std::find_if(st.axes.begin(), st.axes.end(), [](const StudyAxis& a) { return a.formulation(); });
      if (f == st.axes.end() || std::count(f->values.begin(), f->values.end(), st.reference_formulation) == 0)
        r.fail("formulation",
               "one of the values of the study's formulation axis, got '" + st.reference_formulation + "'");
    }
  }
}

// [study.window]: the axis whose usable range is reported, and the limits.
void read_window(CaseSection& w, Study& st) {
  st.window_axis = w.text("axis", std::nullopt);
  if (!has_axis(st, st.window_axis)) w.fail("axis", "the key of one of the study's axes");
  st.window_penetration = w.real("max_penetration_rel", 1e-3, Range::positive());
  st.window_iterations = w.real("max_iterations", 10.0, Range::positive());
}

// [study.regularization]: a numeric axis of positive values falling to the
// reference's limit, the value whose errors are stated, the round-off floors.
void read_regularization(CaseSection& g, Study& st) {
  if (st.reference != StudyReference::Formulation)
    g.fail("axis", "a study whose [study.reference] kind is \"formulation\" (the limit its errors fall to)");
  st.regularization_axis = g.text("axis", std::nullopt);
  const auto ax = std::find_if(st.axes.begin(), st.axes.end(),
                               [&](const StudyAxis& x) { return x.key == st.regularization_axis; });
  if (ax == st.axes.end() || ax->formulation()) g.fail("axis", "the key of one of the study's numeric axes");
  for (const auto* grid : {&ax->values_full, &ax->values_quick})
    for (double v : *grid)
      if (!(v > 0)) g.fail("axis", "an axis of values above 0 (the orders take their logarithm), got " + exact_text(v));
  if (g.has("default")) {
    st.regularization_default = g.real("default", std::nullopt, Range::positive());
    if (std::count(ax->values_full.begin(), ax->values_full.end(), st.regularization_default) == 0)
      g.fail("default", "one of the axis's values, got " + exact_text(st.regularization_default));
  }
  st.load_floor = g.real("floor", 1e-6, Range::nonnegative());
  st.monitor_floor = g.real("monitor_floor", 1e-6, Range::nonnegative());
}

}  // namespace

const std::string& reference_name(StudyReference kind) { return name_of(kReferences, kind); }
const std::string& measure_name(LoadMeasure measure) { return name_of(kMeasures, measure); }

Study read_study(const std::string& path, const std::string& cases_dir, bool quick) {
  CaseFile file(path);
  CaseSection root = file.root();
  CaseSection s = root.required_table("study");
  Study st;
  st.file = path;
  st.name = s.text("name", fs::path(path).stem().string());
  st.description = s.text("description", std::string());
  st.case_file = read_case_path(s, path, cases_dir);
  st.formulation = s.text("formulation", std::string());
  if (!st.formulation.empty()) check_formulation(s, "formulation", st.formulation);
  st.load = s.text("load", std::nullopt);
  st.set = optional_texts(s, "set", "overrides key=value");
  const auto quick_set = optional_texts(s, "quick_set", "overrides key=value under --quick");
  if (quick) st.set.insert(st.set.end(), quick_set.begin(), quick_set.end());
  auto axes = s.table_array("axis");
  if (axes.empty()) s.fail("axis", "at least one [[study.axis]] table");
  for (auto& a : axes) st.axes.push_back(read_axis(a, quick));
  read_reference(s.section("reference"), st);
  if (auto w = s.table("window")) read_window(*w, st);
  if (auto g = s.table("regularization")) read_regularization(*g, st);
  st.monitor = s.text("monitor", std::string());
  if (!st.monitor.empty() && st.reference != StudyReference::Formulation)
    s.fail("monitor", "a study whose [study.reference] kind is \"formulation\" (the monitor is compared against "
                      "the reference run's)");
  file.finish();
  return st;
}

}  // namespace rpfem
