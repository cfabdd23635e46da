// What a parameter sweep measures of each run (from its history.csv), the
// load and monitor errors against a reference run, Richardson's estimate
// from a sequence of refined runs, and the observed order of an error as a
// regularization parameter falls. Values not measured are -1.
#pragma once
#include <string>
#include <vector>

#include "results.hpp"

namespace rpfem {

struct RunMetrics {
  int steps = 0;                  // steps after step 0
  double final_stroke = 0;        // mm
  double final_load = 0;          // kN, |load| at the last step
  double penetration = -1;        // largest max_penetration_rel (penetration / element size)
  double volume_error = 0;        // largest |volume_change|
  double iterations_mean = 0;     // Newton (or Ipopt) iterations per step, steps after step 0
  double iterations_median = 0;   // (all solves of a step: contact re-solves included)
  double iterations_max = 0;
  double iterations_per_solve_median = -1;  // median over the steps of iterations / solves (-1: no solves column)
  double rcond = -1;              // least tangent_rcond (no kernel factorization: -1)
};

// `load`: the history column of the load compared (N).
RunMetrics run_metrics(const History& h, const std::string& load);

// The largest relative difference of |load| from the reference's over the
// run's strokes from `from` mm on (the reference interpolated linearly),
// and at the run's last stroke.
struct LoadError {
  double largest = -1, final = -1;
};
LoadError load_error(const History& run, const History& reference, const std::string& load, double from);

// What `stepping.tolerance` bounds (docs/theory.md, "Step control by a
// local error estimate"): max |F_h - F_ref| over the run's strokes, over
// the largest |F_ref|, the reference interpolated linearly (its end values
// beyond its ends); no stroke within one step (of either run) of either
// run's landing compared, a landing being a step whose history.csv
// `contact_nodes` changes (docs/decisions.md, "Load comparisons away from
// the landings"; a history without the column has none). -1 when nothing
// is compared.
double max_relative_load_error(const History& run, const History& reference, const std::string& load);

// The steps whose count of rows in contact (`contact_nodes`) changes.
std::vector<std::size_t> landing_steps(const History& h);

// The mean of |load| over the run's strokes from `from` mm to its last, kN:
// the work of the load over that stroke divided by the stroke, trapezoidal
// over the recorded steps (the first interval cut at `from`). Averaging
// smooths the staircase of a contact spreading node by node, which a load
// at one stroke carries. -1 when the run does not get past `from`.
double mean_load(const History& h, const std::string& load, double from);

// The largest absolute difference of a history column (a monitor: a ring's
// inner-diameter change in %, a radius in mm) from the reference's over
// the run's strokes from `from` mm on (the reference interpolated linearly
// at the run's strokes within its own), in the column's unit, and at the
// run's last stroke. -1 where no stroke is compared.
LoadError column_difference(const History& run, const History& reference, const std::string& column, double from);

// The relative difference of the mean |load| over the run's strokes from
// `from` mm to its last from the reference's mean over the same strokes
// (mean_load of each; the reference's history cut at the run's last
// stroke): |mean / mean_ref - 1|. -1 when either mean is not measured or
// the reference does not reach the run's last stroke.
double mean_load_error(const History& run, const History& reference, const std::string& load, double from);

// Observed order of an error e(a) against a regularization parameter a
// that falls to 0 towards the reference (e ~ C a^p: p the slope of ln e
// against ln a). The values are taken falling (sorted by a, largest
// first); an error of -1 is not measured, and an error at or below
// `floor` is round-off (or the reference's own accuracy), where the slope
// says nothing of the regularization:
// - successive[k]: the slope between the k-th and (k+1)-th values,
//   ln(e_k / e_{k+1}) / ln(a_k / a_{k+1}), measured where both errors are
//   above the floor;
// - fit: the least-squares slope of ln e against ln a over every value
//   whose error is above the floor, when there are two or more.
struct ObservedOrders {
  std::vector<double> a, e;             // the values falling, their errors
  std::vector<double> successive;       // size a.size() - 1 (0 where not measured)
  std::vector<bool> successive_measured;
  double fit = 0;
  int fit_points = 0;                   // values in the fit; the fit is measured when >= 2
  bool fit_measured() const { return fit_points >= 2; }
};
ObservedOrders observed_orders(std::vector<double> a, std::vector<double> e, double floor);

// Richardson's estimate from values f at sizes h (h > 0; the three
// smallest are used and must have a constant ratio r = h2 / h1 = h3 / h2 > 1
// to within 1e-6): observed order p = ln((f3 - f2) / (f2 - f1)) / ln r and
// the extrapolated value f1 + (f1 - f2) / (r^p - 1). `ok` false (with a
// reason) when there are fewer than three values, the ratio is not
// constant, or the differences do not shrink monotonically.
struct Richardson {
  bool ok = false;
  double order = 0, extrapolated = 0, ratio = 0;
  std::string note;
};
Richardson richardson(std::vector<double> h, std::vector<double> f);

}  // namespace rpfem
