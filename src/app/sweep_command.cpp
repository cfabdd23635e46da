#include "app/sweep_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <toml++/toml.h>

#include "app/run_pool.hpp"
#include "app/study.hpp"
#include "core/types.hpp"
#include "core/version.hpp"
#include "io/case_file.hpp"
#include "io/result_writer.hpp"
#include "io/scene_reader.hpp"
#include "io/table_writer.hpp"
#include "results.hpp"
#include "sweep_metrics.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

struct Point {
  std::vector<std::size_t> index;  // per axis
  PoolRun run;
};

// The grid's points in row-major order (the last axis fastest).
std::vector<Point> grid(const Study& st, const SweepOptions& opt) {
  std::vector<Point> out;
  std::vector<std::size_t> idx(st.axes.size(), 0);
  for (;;) {
    Point p;
    p.index = idx;
    PoolRun& r = p.run;
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
    std::snprintf(dir, sizeof dir, "/runs/%03zu", out.size());
    r.dir = opt.out_dir + dir;
    r.label = st.name + " " + r.label;
    out.push_back(p);
    std::size_t a = st.axes.size();
    while (a > 0 && ++idx[a - 1] == st.axes[a - 1].values.size()) idx[--a] = 0;
    if (a == 0) break;
  }
  return out;
}

// End stroke and planned steps for progress lines (and an early check of
// every run's overrides: bad input stops the sweep before it starts).
void plan_progress(PoolRun& r) {
  CaseFile file(r.case_file, r.overrides);
  const Scene scene = read_scene(file);
  r.end_stroke = scene.stepping.end_stroke;
  r.steps = std::max(1, static_cast<int>(std::ceil(r.end_stroke / scene.stepping.stroke_increment - 1e-9)));
}

History history_or_empty(const std::string& dir) {
  try {
    return read_history(dir + "/history.csv");
  } catch (const std::exception&) {
    return {};
  }
}

double size_of(const std::string& key, double value) { return key == "run.mesh_factor" ? 1.0 / value : value; }

}  // namespace

int sweep_command(const SweepOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const Study st = read_study(opt.study_file, opt.cases_dir, opt.quick);
  std::vector<Point> points = grid(st, opt);
  std::vector<PoolRun> runs;
  for (auto& p : points) {
    plan_progress(p.run);
    runs.push_back(p.run);
  }
  if (st.reference == "formulation") {
    PoolRun ref;
    ref.label = st.name + " reference " + st.reference_formulation;
    ref.case_file = st.case_file, ref.formulation = st.reference_formulation, ref.dir = opt.out_dir + "/reference";
    ref.overrides = st.set;
    ref.overrides.insert(ref.overrides.end(), st.reference_set.begin(), st.reference_set.end());
    ref.overrides.insert(ref.overrides.end(), opt.overrides.begin(), opt.overrides.end());
    plan_progress(ref);
    runs.push_back(ref);
  }
  fs::create_directories(opt.out_dir);
  if (!opt.quiet) std::printf("rpfem sweep %s: %s, results in %s\n", st.name.c_str(), st.description.c_str(), opt.out_dir.c_str());
  run_pool(runs, opt.jobs, opt.quiet);
  for (std::size_t i = 0; i < points.size(); ++i) points[i].run = runs[i];

  // Per run: the history's metrics and the summary's status and timing.
  std::vector<RunMetrics> m(points.size());
  std::vector<History> h(points.size());
  std::vector<LoadError> err(points.size());
  std::vector<bool> finished(points.size());
  std::vector<double> per_step(points.size(), -1);
  std::vector<std::string> formulation(points.size()), reason(points.size());
  const History ref = st.reference == "formulation" ? history_or_empty(runs.back().dir) : History{};
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PoolRun& r = points[i].run;
    h[i] = history_or_empty(r.dir);
    if (h[i].rows() > 0) m[i] = run_metrics(h[i], st.load);
    if (ref.rows() > 1 && h[i].rows() > 1) err[i] = load_error(h[i], ref, st.load, st.from);
    const auto status = summary_string(r.dir, "status");
    finished[i] = status.value_or("") == "finished" && r.rc == 0;
    reason[i] = status ? summary_string(r.dir, "reason").value_or("") : "no summary.json (exit " + std::to_string(r.rc) + ")";
    for (char& c : reason[i])
      if (c == ',' || c == '"' || c == '\n') c = ';';  // one CSV cell
    per_step[i] = summary_number(r.dir, "time_per_step_s").value_or(-1.0);
    formulation[i] = r.formulation.empty() ? summary_string(r.dir, "formulation").value_or("") : r.formulation;
  }

  // Richardson: per combination of the other axes, along the size axis.
  toml::array rich;
  if (st.reference == "richardson") {
    const auto ax = static_cast<std::size_t>(
        std::find_if(st.axes.begin(), st.axes.end(), [&](const StudyAxis& a) { return a.key == st.richardson_axis; }) -
        st.axes.begin());
    std::map<std::vector<std::size_t>, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < points.size(); ++i) {
      auto key = points[i].index;
      key[ax] = 0;
      if (finished[i]) groups[key].push_back(i);
    }
    for (const auto& [key, members] : groups) {
      std::vector<double> hs, fs;
      for (std::size_t i : members) hs.push_back(size_of(st.richardson_axis, st.axes[ax].numbers[points[i].index[ax]])), fs.push_back(m[i].final_load);
      const Richardson r = richardson(hs, fs);
      std::string label;
      for (std::size_t a = 0; a < st.axes.size(); ++a)
        if (a != ax) label += (label.empty() ? "" : " ") + st.axes[a].key + "=" + st.axes[a].values[key[a]];
      rich.push_back(toml::table{{"group", label}, {"ok", r.ok}, {"observed_order", r.ok ? r.order : -1.0},
                                 {"extrapolated_load_kN", r.ok ? r.extrapolated : -1.0}, {"ratio", r.ratio},
                                 {"note", r.note}});
      if (!r.ok) continue;
      for (std::size_t i : members) err[i].final = std::abs(m[i].final_load / r.extrapolated - 1);
    }
  }

  // The table.
  Table t;
  t.columns = {"run", "dir", "formulation"};
  for (const auto& a : st.axes)
    if (!a.formulation()) t.columns.push_back(a.key);
  for (const char* c : {"exit_code", "finished", "steps", "final_stroke_mm", "final_load_kN", "penetration_rel",
                        "load_error", "load_error_final", "volume_error", "iterations_mean", "iterations_median",
                        "iterations_max",
                        "rcond", "wall_time_s", "time_per_step_s", "reason"})
    t.columns.push_back(c);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::map<std::string, double> n{{"run", double(i)},
                                    {"exit_code", double(points[i].run.rc)},
                                    {"finished", finished[i] ? 1.0 : 0.0},
                                    {"steps", double(m[i].steps)},
                                    {"final_stroke_mm", m[i].final_stroke},
                                    {"final_load_kN", m[i].final_load},
                                    {"penetration_rel", m[i].penetration},
                                    {"load_error", err[i].largest},
                                    {"load_error_final", err[i].final},
                                    {"volume_error", m[i].volume_error},
                                    {"iterations_mean", m[i].iterations_mean},
                                    {"iterations_median", m[i].iterations_median},
                                    {"iterations_max", m[i].iterations_max},
                                    {"rcond", m[i].rcond},
                                    {"wall_time_s", points[i].run.seconds},
                                    {"time_per_step_s", per_step[i]}};
    for (std::size_t a = 0; a < st.axes.size(); ++a)
      if (!st.axes[a].formulation()) n[st.axes[a].key] = st.axes[a].numbers[points[i].index[a]];
    std::string f = formulation[i].empty() ? points[i].run.formulation : formulation[i];
    t.add_row(n, {{"dir", fs::relative(points[i].run.dir, opt.out_dir).string()}, {"formulation", f},
                  {"reason", reason[i]}});
  }

  // The usable window of one axis.
  toml::table window;
  if (!st.window_axis.empty()) {
    const auto ax = static_cast<std::size_t>(
        std::find_if(st.axes.begin(), st.axes.end(), [&](const StudyAxis& a) { return a.key == st.window_axis; }) -
        st.axes.begin());
    double lo = INFINITY, hi = -INFINITY;
    toml::array usable;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const bool ok = finished[i] && m[i].penetration >= 0 && m[i].penetration <= st.window_penetration &&
                      m[i].iterations_median <= st.window_iterations;
      if (!ok) continue;
      const double x = st.axes[ax].numbers[points[i].index[ax]];
      lo = std::min(lo, x), hi = std::max(hi, x);
      usable.push_back(x);
    }
    window = toml::table{{"axis", st.window_axis}, {"max_penetration_rel", st.window_penetration},
                         {"max_iterations", st.window_iterations}, {"usable", usable}};
    if (!usable.empty()) {
      window.insert("from", lo), window.insert("to", hi);
      if (lo > 0) window.insert("decades", std::log10(hi / lo));
    }
  }

  toml::array axes, overrides, run_list;
  for (const auto& a : st.axes) {
    toml::array v;
    for (const auto& x : a.values) v.push_back(x);
    axes.push_back(toml::table{{"key", a.key}, {"values", v}});
  }
  for (const auto& o : opt.overrides) overrides.push_back(o);
  for (const auto& p : points) {
    toml::array ov;
    for (const auto& o : p.run.overrides) ov.push_back(o);
    run_list.push_back(toml::table{{"dir", fs::relative(p.run.dir, opt.out_dir).string()},
                                   {"formulation", p.run.formulation}, {"overrides", ov}});
  }
  toml::array base_set;
  for (const auto& o : st.set) base_set.push_back(o);
  toml::table meta{{"study", st.name},
                   {"study_file", fs::absolute(st.file).string()},
                   {"description", st.description},
                   {"case_file", fs::absolute(st.case_file).string()},
                   {"formulation", st.formulation},
                   {"load", st.load},
                   {"quick", opt.quick},
                   {"set", base_set},
                   {"command_line_set", overrides},
                   {"axes", axes},
                   {"reference", toml::table{{"kind", st.reference}, {"formulation", st.reference_formulation},
                                             {"from_mm", st.from}}},
                   {"runs", run_list},
                   {"version", kVersion},
                   {"wall_time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()}};
  if (!rich.empty()) meta.insert("richardson", rich);
  if (!window.empty()) meta.insert("window", window);
  std::ostringstream js;
  js << toml::json_formatter{meta} << "\n";
  write_table_csv(opt.out_dir + "/sweep.csv", t);
  write_table_h5(opt.out_dir + "/sweep.h5", t, js.str());
  write_text_atomically(opt.out_dir + "/sweep.json", js.str());

  int stopped = 0;
  for (bool f : finished) stopped += f ? 0 : 1;
  if (!opt.quiet) {
    std::printf("%s: %zu runs, %d stopped; table %s/sweep.csv\n", st.name.c_str(), points.size(), stopped,
                opt.out_dir.c_str());
    for (auto&& r : rich)
      if (const auto* g = r.as_table())
        std::printf("  Richardson %s: %s\n", (*g)["group"].value_or(std::string()).c_str(),
                    (*g)["ok"].value_or(false)
                        ? ("observed order " + std::to_string((*g)["observed_order"].value_or(0.0)) +
                           ", extrapolated load " + std::to_string((*g)["extrapolated_load_kN"].value_or(0.0)) + " kN")
                              .c_str()
                        : (*g)["note"].value_or(std::string()).c_str());
    if (!window.empty()) {
      if (window.contains("from"))
        std::printf("  usable %s: %g to %g (%.1f decades)\n", st.window_axis.c_str(), window["from"].value_or(0.0),
                    window["to"].value_or(0.0), window["decades"].value_or(0.0));
      else
        std::printf("  usable %s: none of the values\n", st.window_axis.c_str());
    }
  }
  return stopped ? 3 : 0;
}

}  // namespace rpfem
