#include "app/sweep_command.hpp"
#include "app/output_folder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include <toml++/toml.h>

#include "app/case_setup.hpp"
#include "app/run_engine.hpp"
#include "app/study.hpp"
#include "app/sweep_outcomes.hpp"
#include "core/types.hpp"
#include "core/version.hpp"
#include "io/case_file.hpp"
#include "io/result_writer.hpp"
#include "io/table_writer.hpp"
#include "results.hpp"
#include "sweep_metrics.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

// The grid's runs in row-major order (the last axis fastest), each with its
// value's index on each axis.
void grid(SweepPlan& plan) {
  const Study& st = plan.study;
  const SweepOptions& opt = plan.options;
  std::vector<std::size_t> idx(st.axes.size(), 0);
  for (;;) {
    PoolRun r;
    r.case_file = st.case_file;
    r.formulation = st.formulation;
    r.overrides = st.set;
    for (std::size_t a = 0; a < st.axes.size(); ++a) {
      const StudyAxis& ax = st.axes[a];
      const std::string& v = ax.values[idx[a]];
      if (ax.formulation())
        r.formulation = v;
      else
        r.overrides.push_back(ax.key + "=" + v);
      char shown[32];
      if (!ax.formulation()) std::snprintf(shown, sizeof shown, "%g", ax.numbers[idx[a]]);
      r.label += (a ? " " : "") + (ax.formulation() ? v : ax.key.substr(ax.key.rfind('.') + 1) + "=" + shown);
    }
    r.overrides.insert(r.overrides.end(), opt.overrides.begin(), opt.overrides.end());
    char dir[32];
    std::snprintf(dir, sizeof dir, "/runs/%03zu", plan.runs.size());
    r.dir = opt.out_dir + dir;
    r.label = st.name + " " + r.label;
    plan.index.push_back(idx);
    plan.runs.push_back(r);
    std::size_t a = st.axes.size();
    while (a > 0 && ++idx[a - 1] == st.axes[a - 1].values.size()) idx[--a] = 0;
    if (a == 0) break;
  }
}

// A monitor's values are lengths (mm), or changes from the initial value:
// relative, or in percent, whose differences are percentage points.
std::string monitor_unit(const Monitor& m) {
  switch (m.change) {
    case Monitor::Change::Percent: return "percentage points";
    case Monitor::Change::Relative: return "relative change";
    case Monitor::Change::None: break;
  }
  return "mm";
}

// Each run's case read and validated as `rpfem run` will read it (bad
// input, the study's load column among them, stops the sweep before it
// starts), and its end stroke and planned steps for progress lines.
// The study's monitor among the case's too; returns its unit.
std::string plan_run(PoolRun& r, const Study& st) {
  const PreparedCase pc = prepare_case(r.case_file, r.overrides, r.formulation);
  const auto loads = load_columns(pc);
  if (std::find(loads.begin(), loads.end(), st.load) == loads.end()) {
    std::string known;
    for (const auto& l : loads) known += (known.empty() ? "" : ", ") + l;
    throw InputError(st.file + ": key 'study.load': '" + st.load + "' is no load column of " + r.label +
                     "; expected one of: " + known);
  }
  std::string unit;
  if (!st.monitor.empty()) {
    const auto m = std::find_if(pc.monitors.begin(), pc.monitors.end(),
                                [&](const Monitor& x) { return x.name == st.monitor; });
    if (m == pc.monitors.end()) {
      std::string known;
      for (const auto& x : pc.monitors) known += (known.empty() ? "" : ", ") + x.name;
      throw InputError(st.file + ": key 'study.monitor': '" + st.monitor + "' is no monitor of " + r.label +
                       "; expected one of: " + (known.empty() ? "(the case has none)" : known));
    }
    unit = monitor_unit(*m);
  }
  r.end_stroke = pc.scene->stepping.end_stroke;
  r.steps = pc.scene->stepping.planned_steps();
  r.cost = estimated_cost(r.steps, pc.scene->mesh.num_elements());
  return unit;
}


template <class T>
toml::array to_array(const std::vector<T>& v) {
  toml::array a;
  for (const auto& x : v) a.push_back(x);
  return a;
}


double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}


// What a run measured, as a row of the table (and the reference run's own
// values in sweep.json), by column name.
std::map<std::string, double> measured(const Outcome& o, const PoolRun& r) {
  return {{"exit_code", double(r.rc)},
          {"finished", o.finished ? 1.0 : 0.0},
          {"steps", double(o.m.steps)},
          {"final_stroke_mm", o.m.final_stroke},
          {"final_load_kN", o.m.final_load},
          {"mean_load_kN", o.mean_load},
          {"penetration_rel", o.m.penetration},
          {"load_error", o.err.largest},
          {"load_error_final", o.err.final},
          {"mean_load_error", o.mean_load_error},
          {"load_error_max_rel", o.max_relative},
          {"step_rejections", o.rejections},
          {"monitor_error", o.monitor_err.largest},
          {"monitor_error_final", o.monitor_err.final},
          {"volume_error", o.m.volume_error},
          {"iterations_mean", o.m.iterations_mean},
          {"iterations_median", o.m.iterations_median},
          {"iterations_max", o.m.iterations_max},
          {"iterations_per_solve_median", o.m.iterations_per_solve_median},
          {"iterations_discarded", o.discarded},
          {"rcond", o.m.rcond},
          {"wall_time_s", r.seconds},
          {"time_per_step_s", o.per_step}};
}

// The table: a row per grid run, its axis values and measured outcome.
Table sweep_table(const SweepPlan& plan, const std::vector<Outcome>& out) {
  const Study& st = plan.study;
  const std::vector<PoolRun>& runs = plan.runs;
  Table t;
  t.columns = {"run", "dir", "formulation"};
  for (const auto& a : st.axes)
    if (!a.formulation()) t.columns.push_back(a.key);
  for (const char* c : {"exit_code", "finished", "steps", "final_stroke_mm", "final_load_kN", "mean_load_kN",
                        "penetration_rel", "load_error", "load_error_final", "mean_load_error", "load_error_max_rel",
                        "step_rejections", "monitor_error",
                        "monitor_error_final", "volume_error", "iterations_mean", "iterations_median",
                        "iterations_max", "iterations_per_solve_median", "iterations_discarded", "rcond",
                        "wall_time_s", "time_per_step_s",
                        "reason"})
    t.columns.push_back(c);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Outcome& o = out[i];
    std::map<std::string, double> n = measured(o, runs[i]);
    n["run"] = double(i);
    for (std::size_t a = 0; a < st.axes.size(); ++a)
      if (!st.axes[a].formulation()) n[st.axes[a].key] = st.axes[a].numbers[plan.index[i][a]];
    t.add_row(n, {{"dir", fs::relative(runs[i].dir, plan.options.out_dir).string()}, {"formulation", o.formulation},
                  {"reason", o.reason}});
  }
  return t;
}

// The usable window of one axis: the values whose runs finished within
// the penetration and iteration limits (none without a window axis).
std::vector<double> usable_values(const SweepPlan& plan, const std::vector<Outcome>& out) {
  const Study& st = plan.study;
  std::vector<double> usable;
  if (st.window_axis.empty()) return usable;
  const std::size_t ax = axis_index(st, st.window_axis);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (out[i].finished && out[i].m.penetration >= 0 && out[i].m.penetration <= st.window_penetration &&
        out[i].m.iterations_median <= st.window_iterations)
      usable.push_back(st.axes[ax].numbers[plan.index[i][ax]]);
  return usable;
}

// The errors of a group as the regularization value falls, and their orders.
toml::table orders_record(const ObservedOrders& o, double at_default, double floor) {
  toml::array pairs;
  for (std::size_t k = 0; k < o.successive.size(); ++k) {
    toml::table p{{"from", o.a[k]}, {"to", o.a[k + 1]}};
    if (o.successive_measured[k]) p.insert("order", o.successive[k]);
    pairs.push_back(p);
  }
  toml::table t{{"errors", to_array(o.e)}, {"floor", floor}, {"successive", pairs}, {"fit_points", o.fit_points},
                {"error_at_default", at_default}};
  if (o.fit_measured()) t.insert("fit_order", o.fit);
  return t;
}

// The reference run's own values (the table's columns; its errors -1):
// what the reference solution costs.
toml::table reference_record(const SweepPlan& plan, const Outcome& o) {
  const PoolRun& r = plan.runs.back();
  toml::table t{{"dir", fs::relative(r.dir, plan.options.out_dir).string()},
                {"formulation", o.formulation},
                {"reason", o.reason}};
  for (const auto& [k, v] : measured(o, r)) t.insert(k, v);
  if (o.monitor_final) t.insert("monitor_final", *o.monitor_final);
  return t;
}

// Where the runs ran: the engine, and on Slurm the runs per task and how
// they were chosen (--runs-per-task auto: the probe run's time, a run's
// estimate, the task's target, the partition's CPUs).
toml::table engine_record(const EngineChoice& e) {
  toml::table t{{"name", e.engine}};
  if (e.engine != "slurm") return t;
  t.insert("runs_per_task", e.runs_per_task);
  t.insert("runs_per_task_rule", e.rule);
  if (e.rule == "auto") {
    t.insert("probe_run_s", e.probe_run_s);
    t.insert("estimated_run_s", e.estimated_run_s);
    t.insert("task_target_s", e.task_target_s);
    t.insert("cpus", e.cpus);
  }
  return t;
}

// sweep.json: the study, every run's overrides, Richardson's estimates,
// the usable window, the reference run's own values, the regularization's
// orders, version and timings.
toml::table sweep_record(const SweepPlan& plan, const std::vector<Outcome>& out,
                         const std::vector<RichardsonGroup>& rich, const std::vector<RegularizationGroup>& reg,
                         const std::vector<double>& usable) {
  const Study& st = plan.study;
  const SweepOptions& opt = plan.options;
  const std::vector<PoolRun>& runs = plan.runs;
  double runs_time = 0;  // s, the runs' own wall times (the reference's included)
  for (const auto& r : runs) runs_time += r.seconds;
  toml::array axes, run_list, rich_list;
  for (const auto& a : st.axes) axes.push_back(toml::table{{"key", a.key}, {"values", to_array(a.values)}});
  for (std::size_t i = 0; i < plan.index.size(); ++i) {
    toml::table r{{"dir", fs::relative(runs[i].dir, opt.out_dir).string()},
                  {"formulation", runs[i].formulation}, {"overrides", to_array(runs[i].overrides)}};
    if (out[i].monitor_final) r.insert("monitor_final", *out[i].monitor_final);
    run_list.push_back(r);
  }
  for (const auto& g : rich)
    rich_list.push_back(toml::table{{"group", g.label}, {"ok", g.r.ok}, {"observed_order", g.r.ok ? g.r.order : -1.0},
                                    {"extrapolated_load_kN", g.r.ok ? g.r.extrapolated : -1.0},
                                    {"ratio", g.r.ratio}, {"note", g.r.note}});
  toml::table meta{{"study", st.name},
                   {"study_file", fs::absolute(st.file).string()},
                   {"description", st.description},
                   {"case_file", fs::absolute(st.case_file).string()},
                   {"formulation", st.formulation},
                   {"load", st.load},
                   {"quick", opt.quick},
                   {"set", to_array(st.set)},
                   {"command_line_set", to_array(opt.overrides)},
                   {"axes", axes},
                   {"reference", toml::table{{"kind", reference_name(st.reference)},
                                             {"formulation", st.reference_formulation},
                                             {"set", to_array(st.reference_set)},
                                             {"axis", st.richardson_axis}, {"from_mm", st.from},
                                             {"measure", measure_name(st.measure)},
                                             {"error_column", stated_error_column(st)}}},
                   {"runs", run_list},
                   {"engine", engine_record(plan.engine)},
                   {"version", kVersion},
                   {"wall_time_s", seconds_since(plan.start)},
                   {"runs_time_s", runs_time}};
  if (!rich.empty()) meta.insert("richardson", rich_list);
  if (!st.monitor.empty()) meta.insert("monitor", toml::table{{"column", st.monitor}, {"unit", plan.monitor_unit}});
  if (has_reference_run(st)) meta.insert("reference_run", reference_record(plan, reference_outcome(plan)));
  if (st.reference == StudyReference::Exact)
    meta.insert("exact", toml::table{{"solution", st.exact_solution}, {"body", st.exact_body},
                                     {"diameter_mm", st.exact_diameter}, {"height_mm", st.exact_height},
                                     {"height_per_stroke", st.exact_height_per_stroke},
                                     {"K_MPa", plan.exact_law.K}, {"n", plan.exact_law.n},
                                     {"eps0", plan.exact_law.eps0}});
  if (!st.regularization_axis.empty()) {
    toml::array groups;
    for (const auto& g : reg) {
      toml::array dirs;
      for (std::size_t i : g.runs) dirs.push_back(fs::relative(runs[i].dir, opt.out_dir).string());
      toml::table e{{"group", g.label}, {"values", to_array(g.load.a)}, {"dirs", dirs},
                    {"load", orders_record(g.load, g.load_at_default, st.load_floor)}};
      if (!st.monitor.empty()) e.insert("monitor", orders_record(g.monitor, g.monitor_at_default, st.monitor_floor));
      groups.push_back(e);
    }
    meta.insert("regularization",
                toml::table{{"axis", st.regularization_axis},
                            {"default", st.regularization_default},
                            {"load_error", stated_error_column(st)},
                            {"monitor_error", st.monitor.empty() ? "" : "monitor_error_final"},
                            {"groups", groups}});
  }
  if (!st.window_axis.empty()) {
    toml::table w{{"axis", st.window_axis}, {"max_penetration_rel", st.window_penetration},
                  {"max_iterations", st.window_iterations}, {"usable", to_array(usable)}};
    if (!usable.empty()) {
      const auto [lo, hi] = std::minmax_element(usable.begin(), usable.end());
      w.insert("from", *lo), w.insert("to", *hi);
      if (*lo > 0) w.insert("decades", std::log10(*hi / *lo));
    }
    meta.insert("window", w);
  }
  return meta;
}

// "order 1.02 (fit over 5 values)" or "no order (fewer than two errors above 1e-06)".
std::string order_text(const ObservedOrders& o, double floor) {
  char b[96];
  if (o.fit_measured())
    std::snprintf(b, sizeof b, "order %.2f (fit over %d values)", o.fit, o.fit_points);
  else
    std::snprintf(b, sizeof b, "no order (fewer than two errors above %g)", floor);
  return b;
}

// The summary lines: runs and stops, the regularization's orders,
// Richardson's estimates, the window.
void print_sweep(const SweepPlan& plan, long stopped, const std::vector<RichardsonGroup>& rich,
                 const std::vector<RegularizationGroup>& reg, const std::vector<double>& usable) {
  const Study& st = plan.study;
  std::printf("%s: %zu runs, %ld stopped; table %s/sweep.csv\n", st.name.c_str(), plan.index.size(), stopped,
              plan.options.out_dir.c_str());
  for (const auto& g : reg) {
    std::printf("  %s as %s falls: load error %s", g.label.c_str(), st.regularization_axis.c_str(),
                order_text(g.load, st.load_floor).c_str());
    if (!st.monitor.empty())
      std::printf(", %s error %s", st.monitor.c_str(), order_text(g.monitor, st.monitor_floor).c_str());
    if (g.load_at_default >= 0) {
      std::printf("; at %g: %.2e", st.regularization_default, g.load_at_default);
      if (g.monitor_at_default >= 0) std::printf(", %.3g %s", g.monitor_at_default, plan.monitor_unit.c_str());
    }
    std::printf("\n");
  }
  for (const auto& g : rich) {
    if (g.r.ok)
      std::printf("  Richardson %s: observed order %.3f, extrapolated %s load %.6g kN\n", g.label.c_str(), g.r.order,
                  measure_name(st.measure).c_str(), g.r.extrapolated);
    else
      std::printf("  Richardson %s: %s\n", g.label.c_str(), g.r.note.c_str());
  }
  if (!st.window_axis.empty() && usable.empty())
    std::printf("  usable %s: none of the values\n", st.window_axis.c_str());
  if (!usable.empty()) {
    const auto [lo, hi] = std::minmax_element(usable.begin(), usable.end());
    std::printf("  usable %s: %g to %g (%.1f decades)\n", st.window_axis.c_str(), *lo, *hi,
                *lo > 0 ? std::log10(*hi / *lo) : 0.0);
  }
}

// Reference kind "exact": the law of the study's body (its only one when
// the study names none), rate-independent (the closed form's flow stress
// is sigma_bar(eps)); the body's height reaches 0 nowhere on the stroke.
FlowStressLaw exact_law(SweepPlan& plan) {
  Study& st = plan.study;
  const PreparedCase pc = prepare_case(st.case_file, plan.runs.front().overrides, plan.runs.front().formulation);
  const auto& bodies = pc.scene->bodies;
  auto fail = [&](const std::string& key, const std::string& expected) {
    throw InputError(st.file + ": key 'study.reference." + key + "': expected " + expected);
  };
  if (st.exact_body.empty()) {
    if (bodies.size() != 1) fail("body", "the body whose law the exact load takes (the case has several)");
    st.exact_body = bodies.front().name;
  }
  const auto b = std::find_if(bodies.begin(), bodies.end(), [&](const BodySpec& x) { return x.name == st.exact_body; });
  if (b == bodies.end()) fail("body", "a body of the case, got '" + st.exact_body + "'");
  if (b->law.m != 0) fail("body", "a body of rate-independent law (the closed form has no strain rate)");
  if (st.exact_height - st.exact_height_per_stroke * pc.scene->stepping.end_stroke <= 0)
    fail("height_per_stroke", "a height H0 - height_per_stroke * end_stroke above 0");
  return b->law;
}

}  // namespace

SweepPlan plan_sweep(const SweepOptions& opt) {
  SweepPlan plan;
  plan.start = std::chrono::steady_clock::now();
  plan.options = opt;
  plan.study = read_study(opt.study_file, opt.cases_dir, opt.quick);
  const Study& st = plan.study;
  grid(plan);
  if (has_reference_run(st)) {
    PoolRun ref;
    ref.label = st.name + " reference " + st.reference_formulation;
    ref.case_file = st.case_file, ref.formulation = st.reference_formulation, ref.dir = opt.out_dir + "/reference";
    ref.overrides = st.set;
    ref.overrides.insert(ref.overrides.end(), st.reference_set.begin(), st.reference_set.end());
    ref.overrides.insert(ref.overrides.end(), opt.overrides.begin(), opt.overrides.end());
    plan.runs.push_back(ref);
  }
  for (auto& r : plan.runs) plan.monitor_unit = plan_run(r, st);
  if (st.reference == StudyReference::Exact) plan.exact_law = exact_law(plan);
  return plan;
}

int sweep_command(const SweepOptions& opt) {
  SweepPlan plan = plan_sweep(opt);
  claim_output_folder(opt.out_dir, existing_output(opt.force, opt.engine.resume), true);
  if (!opt.quiet)
    std::printf("rpfem sweep %s: %s, results in %s\n", plan.study.name.c_str(), plan.study.description.c_str(),
                opt.out_dir.c_str());
  plan.engine = run_runs(plan.runs, opt.out_dir, opt.engine, opt.jobs, opt.quiet);
  return write_sweep(plan) ? 3 : 0;
}

int write_sweep(const SweepPlan& plan) {
  const SweepOptions& opt = plan.options;
  make_output_folder(opt.out_dir);
  std::vector<Outcome> out = outcomes(plan);
  std::vector<RichardsonGroup> rich;
  if (plan.study.reference == StudyReference::Richardson) rich = richardson_groups(plan, out);
  std::vector<RegularizationGroup> reg;
  if (!plan.study.regularization_axis.empty()) reg = regularization_groups(plan, out);
  const Table t = sweep_table(plan, out);
  const std::vector<double> usable = usable_values(plan, out);
  std::ostringstream js;
  js << toml::json_formatter{sweep_record(plan, out, rich, reg, usable)} << "\n";
  write_table_csv(opt.out_dir + "/sweep.csv", t);
  write_table_h5(opt.out_dir + "/sweep.h5", t, js.str());
  write_text_atomically(opt.out_dir + "/sweep.json", js.str());

  const auto stopped = std::count_if(out.begin(), out.end(), [](const Outcome& o) { return !o.finished; });
  if (!opt.quiet) print_sweep(plan, static_cast<long>(stopped), rich, reg, usable);
  return static_cast<int>(stopped);
}

}  // namespace rpfem
