// A study file (cases/studies/*.toml): one scene run over a grid of
// numerical parameters by `rpfem sweep`. Keys (defaults in brackets):
//   [study]
//   name         [the file's name]
//   description  [""]
//   case         a scene of the cases folder ("paper_test2_die") or a case
//                file path relative to the study file (ending .toml)
//   formulation  [the case's run.formulation]
//   load         history column of the load compared, N ("punch.Fy")
//   monitor      [""] a history column of one of the case's [[monitors]]
//                ("inner_diameter_mid") compared against the reference
//                run's at the same strokes, in its own unit (needs a
//                reference of kind "formulation")
//   set          [[]] overrides of every run and of the reference ("k=v")
//   quick_set    [[]] further overrides under --quick
//   [[study.axis]]  one or more; the grid is their product
//   key          a case key ("formulations.penalty.beta_factor") or
//                "formulation"
//   values       numbers (strings for "formulation")
//   quick        [values] the reduced grid under --quick
//   [study.reference]  what the load error is measured against
//   kind         ["none"] "formulation": one more run with `formulation`
//                and `set` (added to the study's): with a finer fixed
//                step or mesh, the documented converged run; "exact": a
//                closed-form load at each run's strokes (below); "richardson": the
//                estimate from the three finest values of the `axis`
//                (size h = 1 / value for run.mesh_factor, h = value for any
//                other key), per combination of the other axes; with
//                `formulation` (a value of the formulation axis), that
//                formulation's estimate is every formulation's reference
//   formulation, set, axis  as above
//   solution     kind "exact": "upsetting_axisymmetric", the homogeneous
//                frictionless upsetting of a cylinder (verification/
//                analytic.hpp), F = sigma_bar(ln(H0/H)) A0 H0 / H with
//   diameter, height   D0 and H0, mm, and H = H0 - height_per_stroke *
//   height_per_stroke  stroke [2: a half model, both dies approaching],
//   body         [the case's only body] whose (rate-independent) law
//   measure      ["final"] the load compared: "final", at the last
//                stroke; "mean", averaged over the strokes from `from`
//                (work / stroke: smooth where contact spreads node by
//                node); "max_relative" (kinds "formulation" and "exact"),
//                what `stepping.tolerance` bounds: max over the run's
//                strokes of |F_h - F| / max |F|, no stroke within one step
//                of a landing compared (docs/theory.md, "Step control by
//                a local error estimate"). Richardson estimates it; against a reference
//                it is the error the regularization's orders are taken of
//   from         [0] mm: the load error counts strokes from here on
//   [study.window]  the usable range of one axis (e.g. beta): the runs that
//   axis         finished with penetration <= max_penetration_rel [1e-3]
//   max_penetration_rel, max_iterations   and a median over the steps of
//                at most max_iterations [10] iterations per step
//   [study.regularization]  an axis whose limit as it falls to 0 is the
//                reference (the arctan friction law's smoothing speed
//                against the exact law): the errors' observed orders
//   axis         a numeric axis, values > 0
//   default      [none] one of its `values` (the quick grid may leave it
//                out): the errors there are stated (the case's own value)
//   floor        [1e-6] relative load errors at or below it are round-off,
//                left out of the orders
//   monitor_floor  [1e-6] the same for the monitor's error, in its unit
#pragma once
#include <string>
#include <vector>

namespace rpfem {

struct StudyAxis {
  std::string key;
  std::vector<std::string> values;  // as written into --set (numbers: exact_text, so integer keys take whole values)
  std::vector<double> numbers;      // empty for "formulation"
  std::vector<double> values_full, values_quick;  // numbers of either grid (`numbers` is the one in use)
  bool formulation() const { return key == "formulation"; }
};

// [study.reference] kind: what the load error is measured against.
enum class StudyReference { None, Formulation, Richardson, Exact };
// [study.reference] measure: the load error the study states.
enum class LoadMeasure { Final, Mean, MaxRelative };

// Their names as a study file writes them ("none", "final", ...).
const std::string& reference_name(StudyReference kind);
const std::string& measure_name(LoadMeasure measure);

struct Study {
  std::string file, name, description, case_file, formulation, load;
  std::vector<std::string> set;
  std::vector<StudyAxis> axes;
  StudyReference reference = StudyReference::None;
  std::string reference_formulation, richardson_axis;
  LoadMeasure measure = LoadMeasure::Final;
  // kind "exact": the closed form and its data (mm).
  std::string exact_solution, exact_body;
  double exact_diameter = 0, exact_height = 0, exact_height_per_stroke = 2;
  std::vector<std::string> reference_set;
  double from = 0;
  std::string window_axis;
  double window_penetration = -1, window_iterations = -1;
  std::string monitor;
  std::string regularization_axis;
  double regularization_default = -1;  // -1: none
  double load_floor = 1e-6, monitor_floor = 1e-6;
};

// The study runs one more run, its reference formulation's.
inline bool has_reference_run(const Study& st) { return st.reference == StudyReference::Formulation; }
// A reference load at every stroke: a run's or the exact one.
inline bool has_reference_load(const Study& st) {
  return st.reference == StudyReference::Formulation || st.reference == StudyReference::Exact;
}

// Reads and validates a study; InputError naming the file and key. Under
// quick the axes hold their quick values and quick_set is appended to set.
Study read_study(const std::string& path, const std::string& cases_dir, bool quick);

}  // namespace rpfem
