// What a parameter sweep measures of each run (from its history.csv), the
// load error against a reference run, and Richardson's estimate from a
// sequence of refined runs. Values not measured are -1.
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

// The mean of |load| over the run's strokes from `from` mm to its last, kN:
// the work of the load over that stroke divided by the stroke, trapezoidal
// over the recorded steps (the first interval cut at `from`). Averaging
// smooths the staircase of a contact spreading node by node, which a load
// at one stroke carries. -1 when the run does not get past `from`.
double mean_load(const History& h, const std::string& load, double from);

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
