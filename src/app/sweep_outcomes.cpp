#include "app/sweep_outcomes.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "analytic.hpp"

namespace rpfem {

namespace {

History history_or_empty(const std::string& dir) {
  try {
    return read_history(dir + "/history.csv");
  } catch (const std::exception&) {
    return {};
  }
}

double size_of(const std::string& key, double value) { return key == "run.mesh_factor" ? 1.0 / value : value; }

Outcome outcome(const PoolRun& r, const Study& st, const History& ref) {
  Outcome o;
  const History h = history_or_empty(r.dir);
  const bool monitored = !st.monitor.empty() && h.data.count(st.monitor) > 0;
  if (h.rows() > 0) o.m = run_metrics(h, st.load), o.mean_load = mean_load(h, st.load, st.from);
  if (h.rows() > 0 && monitored) o.monitor_final = h.at(st.monitor).back();
  if (ref.rows() > 1 && h.rows() > 1) {
    o.err = load_error(h, ref, st.load, st.from);
    o.mean_load_error = mean_load_error(h, ref, st.load, st.from);
    if (monitored && ref.data.count(st.monitor)) o.monitor_err = column_difference(h, ref, st.monitor, st.from);
  }
  if (ref.rows() > 0 && h.rows() > 0) o.max_relative = max_relative_load_error(h, ref, st.load);
  const Summary s(r.dir);
  const auto status = s.string("status");
  o.finished = status.value_or("") == "finished" && r.rc == 0;
  o.reason = status ? s.string("reason").value_or("") : "no summary.json (exit " + std::to_string(r.rc) + ")";
  for (char& c : o.reason)
    if (c == ',' || c == '"' || c == '\n') c = ';';  // one CSV cell
  o.per_step = s.number("time_per_step_s").value_or(-1.0);
  o.rejections = s.number("total_step_rejections").value_or(-1.0);
  o.discarded = s.number("discarded_newton_iterations").value_or(-1.0);
  o.formulation = r.formulation.empty() ? s.string("formulation").value_or("") : r.formulation;
  return o;
}

// Reference kind "exact": the closed-form load at the run's own strokes
// (the study's load column, pressing: negative as a die's Fy), H = H0 -
// height_per_stroke * stroke.
History exact_history(const SweepPlan& plan, const std::string& dir) {
  const Study& st = plan.study;
  History ex;
  const History h = history_or_empty(dir);
  if (h.rows() == 0) return ex;
  std::vector<double>& load = ex.data[st.load];
  ex.data["stroke"] = h.at("stroke");
  for (double s : h.at("stroke"))
    load.push_back(-upsetting_load_axisymmetric(plan.exact_law, st.exact_diameter, st.exact_height,
                                                st.exact_height - st.exact_height_per_stroke * s));
  return ex;
}

}  // namespace

std::size_t axis_index(const Study& st, const std::string& key) {
  const auto it = std::find_if(st.axes.begin(), st.axes.end(), [&](const StudyAxis& a) { return a.key == key; });
  return static_cast<std::size_t>(it - st.axes.begin());  // read_study checked the key
}

std::vector<Outcome> outcomes(const SweepPlan& plan) {
  const Study& st = plan.study;
  const History ref = has_reference_run(st) ? history_or_empty(plan.runs.back().dir) : History{};
  std::vector<Outcome> out(plan.index.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = outcome(plan.runs[i], st,
                     st.reference == StudyReference::Exact ? exact_history(plan, plan.runs[i].dir) : ref);
  return out;
}

Outcome reference_outcome(const SweepPlan& plan) { return outcome(plan.runs.back(), plan.study, History{}); }

double stated_error(const Study& st, const Outcome& o) {
  switch (st.measure) {
    case LoadMeasure::Mean: return o.mean_load_error;
    case LoadMeasure::MaxRelative: return o.max_relative;
    case LoadMeasure::Final: break;
  }
  return o.err.final;
}

const char* stated_error_column(const Study& st) {
  switch (st.measure) {
    case LoadMeasure::Mean: return "mean_load_error";
    case LoadMeasure::MaxRelative: return "load_error_max_rel";
    case LoadMeasure::Final: break;
  }
  return "load_error_final";
}

std::vector<RegularizationGroup> regularization_groups(const SweepPlan& plan, const std::vector<Outcome>& out) {
  const Study& st = plan.study;
  const std::size_t ax = axis_index(st, st.regularization_axis);
  std::map<std::vector<std::size_t>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < out.size(); ++i) {
    auto key = plan.index[i];
    key[ax] = 0;
    groups[key].push_back(i);
  }
  auto value = [&](std::size_t i) { return st.axes[ax].numbers[plan.index[i][ax]]; };
  std::vector<RegularizationGroup> list;
  for (auto& [key, members] : groups) {
    RegularizationGroup g;
    for (std::size_t a = 0; a < st.axes.size(); ++a)
      if (a != ax)
        g.label += (g.label.empty() ? "" : " ") + (st.axes[a].formulation() ? "formulation" : st.axes[a].key) + "=" +
                   st.axes[a].values[key[a]];
    if (g.label.empty()) g.label = "(all runs)";
    std::sort(members.begin(), members.end(), [&](std::size_t i, std::size_t j) { return value(i) > value(j); });
    g.runs = members;
    // A run that stopped is not compared: its errors are at another stroke.
    std::vector<double> a, el, em;
    for (std::size_t i : members) {
      const double load = stated_error(st, out[i]);
      a.push_back(value(i));
      el.push_back(out[i].finished ? load : -1.0);
      em.push_back(out[i].finished ? out[i].monitor_err.final : -1.0);
      if (value(i) == st.regularization_default) g.load_at_default = el.back(), g.monitor_at_default = em.back();
    }
    g.load = observed_orders(a, el, st.load_floor);
    g.monitor = observed_orders(a, em, st.monitor_floor);
    list.push_back(g);
  }
  return list;
}

std::vector<RichardsonGroup> richardson_groups(const SweepPlan& plan, std::vector<Outcome>& out) {
  const Study& st = plan.study;
  const std::vector<PoolRun>& runs = plan.runs;
  const std::size_t n = out.size();
  std::vector<RichardsonGroup> rich;
  const std::size_t ax = axis_index(st, st.richardson_axis);
  const bool common = !st.reference_formulation.empty();
  const std::size_t fax = common ? axis_index(st, "formulation") : st.axes.size();
  auto group_of = [&](std::size_t i) {
    auto key = plan.index[i];
    key[ax] = 0;
    if (common) key[fax] = 0;
    return key;
  };
  auto compared = [&](std::size_t i) {
    return st.measure == LoadMeasure::Mean ? out[i].mean_load : out[i].m.final_load;
  };
  std::map<std::vector<std::size_t>, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < n; ++i)
    if (out[i].finished && (!common || runs[i].formulation == st.reference_formulation))
      groups[group_of(i)].push_back(i);
  for (const auto& [key, members] : groups) {
    std::vector<double> hs, fs;
    for (std::size_t i : members) {
      hs.push_back(size_of(st.richardson_axis, st.axes[ax].numbers[plan.index[i][ax]]));
      fs.push_back(compared(i));
    }
    // label: the other axes, if any
    RichardsonGroup g{common ? "formulation=" + st.reference_formulation : "", richardson(hs, fs)};
    for (std::size_t a = 0; a < st.axes.size(); ++a)
      if (a != ax && a != fax)
        g.label += (g.label.empty() ? "" : " ") + st.axes[a].key + "=" + st.axes[a].values[key[a]];
    if (g.label.empty()) g.label = "(all runs)";
    if (g.r.ok)
      for (std::size_t i = 0; i < n; ++i)
        if (out[i].finished && group_of(i) == key) out[i].err.final = std::abs(compared(i) / g.r.extrapolated - 1);
    rich.push_back(g);
  }
  return rich;
}

}  // namespace rpfem
