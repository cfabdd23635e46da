// What a sweep measured of its runs (app/sweep_command.hpp; docs/sweeps.md):
// per run its history's metrics, its load and monitor errors against the
// study's reference (a reference run, or the exact load), its status and
// timing; along a regularization axis the errors' observed orders; along
// a size axis Richardson's estimates.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "app/sweep_command.hpp"
#include "results.hpp"
#include "sweep_metrics.hpp"

namespace rpfem {

// What the sweep measured of one run.
struct Outcome {
  RunMetrics m;
  LoadError err;
  LoadError monitor_err;        // the study's monitor against the reference's, in its unit
  double mean_load_error = -1;  // |mean load / the reference's - 1|
  double max_relative = -1;     // what stepping.tolerance bounds (max_relative_load_error)
  double rejections = -1;       // summary.json total_step_rejections (step control only)
  double discarded = -1;        // summary.json discarded_newton_iterations
  bool finished = false;
  double mean_load = -1;  // kN, over the strokes from the study's `from`
  std::optional<double> monitor_final;  // the monitor at the last stroke (any sign: not a table column)
  double per_step = -1;   // s, the summary's time per step
  std::string formulation, reason;
};

// Per grid run: the history's metrics and the summary's status and timing,
// the load errors against the reference run or the exact load if the
// study has one.
std::vector<Outcome> outcomes(const SweepPlan& plan);

// The reference run's own outcome (its errors not measured).
Outcome reference_outcome(const SweepPlan& plan);

// The load error the study's measure names (against a reference), and its
// column of the table.
double stated_error(const Study& st, const Outcome& o);
const char* stated_error_column(const Study& st);

// The index of the study's axis of key `key` (read_study checked it).
std::size_t axis_index(const Study& st, const std::string& key);

// Along the regularization axis, per combination of the other axes (the
// formulation among them): each run's errors as the value falls, their
// observed orders (sweep_metrics.hpp) and the errors at the default value.
struct RegularizationGroup {
  std::string label;  // the other axes' values
  std::vector<std::size_t> runs;  // falling along the axis
  ObservedOrders load, monitor;
  double load_at_default = -1, monitor_at_default = -1;
};
std::vector<RegularizationGroup> regularization_groups(const SweepPlan& plan, const std::vector<Outcome>& out);

// Richardson: along the size axis, per combination of the other axes;
// with a reference formulation, that formulation's estimate serves the
// runs of every formulation at the same other values. Sets each finished
// run's load_error_final against its group's estimate.
struct RichardsonGroup {
  std::string label;  // the other axes' values
  Richardson r;
};
std::vector<RichardsonGroup> richardson_groups(const SweepPlan& plan, std::vector<Outcome>& out);

}  // namespace rpfem
