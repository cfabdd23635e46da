#include "app/run_observer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "mesh/polygon_quad_mesher.hpp"

namespace rpfem {

namespace {

toml::array pair(const Vec2& v) { return toml::array{v(0), v(1)}; }
std::string to_json(const toml::table& t) {
  std::ostringstream os;
  os << toml::json_formatter{t};
  return os.str();
}
}  // namespace

RunObserver::RunObserver(const Scene& scene, const std::string& dir, toml::table summary, bool quiet,
                         std::vector<Monitor> monitors)
    : scene_(scene), dir_(dir), summary_(std::move(summary)), quiet_(quiet), monitors_(std::move(monitors)),
      t0_(std::chrono::steady_clock::now()) {
  summary_.insert_or_assign("status", "running");
  toml::array mons;
  for (const auto& m : monitors_) {
    toml::table t{{"name", m.name}, {"side", m.side}, {"quantity", m.quantity_name}, {"initial_mm", m.initial}};
    t.insert("change", m.change == Monitor::Change::None       ? "none"
                       : m.change == Monitor::Change::Relative ? "relative"
                                                               : "percent");
    mons.push_back(t);
  }
  summary_.insert_or_assign("monitors", mons);
  writer_ = std::make_unique<ResultWriter>(dir_, scene_.mesh, to_json(summary_));
  mesh_nodes_ = scene_.mesh.num_nodes(), mesh_elements_ = scene_.mesh.num_elements();
  // The dies' arcs drawn to a thousandth of the finest body's element size.
  const auto& sizes = scene_.remesh.size;
  die_sagitta_ = 1e-3 * (sizes.empty() ? 0.01 * scene_.mesh.size() : *std::min_element(sizes.begin(), sizes.end()));
  const auto& s = scene_.stepping;
  expected_steps_ = s.planned_steps();
}

StepFields RunObserver::fields(const StepRecord& r) const {
  StepFields f;
  f.step = r.step;
  f.time = r.time;
  f.stroke = r.stroke;
  f.x = &r.x;
  f.v = &r.v;
  f.strain_rate = &r.strain_rate;
  f.strain = &r.strain;
  f.mean_stress = &r.mean_stress;
  f.element_scalars["flow_stress"] = r.flow_stress;
  f.element_scalars["strain_rate_error"] = r.strain_rate_error;
  f.node_scalars = r.node_fields;
  // The values history.csv has for the step: its loads and monitors.
  for (std::size_t i = 0; i < load_names_.size() && i < r.loads.size(); ++i) {
    f.globals.push_back({load_names_[i] + ".Fx", r.loads[i](0)});
    f.globals.push_back({load_names_[i] + ".Fy", r.loads[i](1)});
  }
  const std::vector<double> mons = evaluate_monitors(monitors_, r.x);
  for (std::size_t i = 0; i < monitors_.size(); ++i) f.globals.push_back({monitors_[i].name, mons[i]});
  for (const Die& d : scene_.dies) f.dies.push_back({d.name, d.profile.polyline(d.motion.displacement(r.time), die_sagitta_)});
  return f;
}

void RunObserver::on_start(const DerivedParameters& d, const std::vector<std::string>& load_names,
                           const std::vector<std::string>& report_names) {
  if (history_) return;  // a run resumed after a remesh: the files go on
  load_names_ = load_names;
  toml::table derived{{"reference_speed_mm_s", d.reference_speed},
                      {"reference_length_mm", d.reference_length},
                      {"reference_strain_rate_1_s", d.reference_strain_rate},
                      {"force_scale_floor_N", d.force_floor},
                      {"limiting_strain_rate_1_s", d.limiting_strain_rate},
                      {"regularization_s", d.regularization},
                      {"dt_nominal_s", d.dt_nominal}};
  toml::table alpha;
  for (std::size_t b = 0; b < d.alpha.size(); ++b) alpha.insert(scene_.bodies[b].name, d.alpha[b]);
  derived.insert("alpha_MPa_s", alpha);
  if (!d.contact.empty()) {
    toml::table contact;
    for (const auto& nv : d.contact) contact.insert(nv.name, nv.value);
    derived.insert("contact", contact);
  }
  summary_.insert_or_assign("derived", derived);
  std::vector<std::string> cols{"step", "time", "stroke"};
  for (const auto& n : load_names) {
    cols.push_back(n + ".Fx");
    cols.push_back(n + ".Fy");
  }
  for (const auto& c : {"newton_iterations", "contact_passes", "solves", "residual", "tangent_rcond", "volume",
                        "volume_change", "dt", "cuts", "min_scaled_jacobian", "rigid_points", "strain_rate_error"})
    cols.push_back(c);
  // Step control (stepping.tolerance): the step's increment (mm), its
  // local error estimate and the estimate's bound (model/step_control.hpp).
  if (scene_.stepping.tolerance > 0)
    for (const auto& c : {"increment", "step_error", "step_error_bound"}) cols.push_back(c);
  for (const auto& n : report_names) cols.push_back(n);
  for (const auto& m : monitors_) cols.push_back(m.name);
  history_ = std::make_unique<HistoryWriter>(dir_ + "/history.csv", cols);
  events_path_ = dir_ + "/events.csv";
  write_text_atomically(events_path_, "step,time,attempt,event\n");
  write_summary();
}

void RunObserver::on_step(const StepRecord& r) {
  if (r.step == 0) initial_volume_ = r.volume;
  const double dv = r.volume / initial_volume_ - 1.0;
  max_volume_change_ = std::max(max_volume_change_, std::abs(dv));
  min_quality_ = std::min(min_quality_, r.min_scaled_jacobian);
  std::vector<double> row{double(r.step), r.time, r.stroke};
  for (const Vec2& l : r.loads) {
    row.push_back(l(0));
    row.push_back(l(1));
  }
  for (double v :
       {double(r.newton_iterations), double(r.contact_passes), double(r.solves), r.residual, r.tangent_rcond, r.volume,
        dv, r.dt, double(r.cuts), r.min_scaled_jacobian, double(r.rigid_points), r.strain_rate_error_relative})
    row.push_back(v);
  if (scene_.stepping.tolerance > 0)
    for (double v : {r.stroke - last_.stroke, r.step_error, r.step_error_bound}) row.push_back(r.step == 0 ? 0.0 : v);
  row.insert(row.end(), r.contact_report.begin(), r.contact_report.end());
  for (double v : evaluate_monitors(monitors_, r.x)) row.push_back(v);
  history_->write_row(row);
  const std::size_t k = press_load();
  if (jump_pending_ && k < r.loads.size() && !recent_.empty()) {
    // The first step after a remesh against the trend before it: the line
    // from the remesh's step along the last step's slope dF/ds, or, where
    // a node landed in that step, along the latest of the two steps before
    // without a landing (a node folding onto a die: the ring's load rose
    // 4.9 % in the step of a remesh, and that slope is no trend).
    double m = 0;
    for (std::size_t i = recent_.size(); i-- > 1;) {
      const Recent &p = recent_[i - 1], &q = recent_[i];
      if (!(q.stroke > p.stroke)) continue;
      m = (q.load - p.load) / (q.stroke - p.stroke);
      if (!q.landed) break;
    }
    const double line = recent_.back().load + m * (r.stroke - recent_.back().stroke);
    const double jump = line > 0 ? std::abs(r.loads[k].norm() - line) / line : 0.0;
    auto* entry = remeshes_.back().as_table();
    entry->insert_or_assign("load_jump_trend", jump);
    summary_.insert_or_assign("remeshes", remeshes_);
    std::ostringstream text;
    text << "remesh next step's load against the trend " << jump;
    write_events(r.step, r.time, {text.str()});
    jump_pending_ = false;
  }
  write_events(r.step, r.time, r.events);
  if (r.step % scene_.stepping.output_every == 0) {
    writer_->write_step(fields(r));
    last_field_step_ = r.step;
  }
  if (k < r.loads.size()) {
    recent_.push_back({r.stroke, r.loads[k].norm(), r.landing});
    if (recent_.size() > 4) recent_.pop_front();
  }
  last_ = r;
  last_step_ = r.step;
  if (!quiet_ && (r.step % std::max(1, expected_steps_ / 20) == 0 || r.step == expected_steps_)) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const double frac = std::min(1.0, r.stroke / scene_.stepping.end_stroke);
    std::printf("  step %5d  stroke %8.4f mm (%3.0f%%)  newton %2d  residual %.1e  %6.1f s elapsed",
                r.step, r.stroke, 100 * frac, r.newton_iterations, r.residual, el);
    if (frac > 0.02) std::printf(", ~%.0f s left", el * (1 - frac) / frac);
    std::printf("\n");
    std::fflush(stdout);
  }
  if (r.step % 10 == 0) write_summary();
}

std::size_t RunObserver::press_load() const {
  for (std::size_t i = 0; i < load_names_.size() && i < last_.loads.size(); ++i)
    if (load_names_[i] == scene_.stepping.reference) return i;
  std::size_t k = 0;
  for (std::size_t i = 1; i < last_.loads.size(); ++i)
    if (last_.loads[i].norm() > last_.loads[k].norm()) k = i;
  return k;
}

std::vector<Index> RunObserver::pinned_nodes() const {
  std::vector<Index> nodes;
  for (const Monitor& m : monitors_)
    if (m.quantity == Monitor::Quantity::XNear || m.quantity == Monitor::Quantity::YNear)
      nodes.insert(nodes.end(), m.nodes.begin(), m.nodes.end());
  return nodes;
}

void RunObserver::remeshed(const RemeshedScene& re, const std::string& why, const RemeshChange& c) {
  const Mesh& m = re.scene.mesh;
  // The remeshed step's fields on their own mesh, whatever output_every
  // says: the last step on the old mesh is then always on record.
  if (last_field_step_ != last_step_) {
    writer_->write_step(fields(last_));
    last_field_step_ = last_step_;
  }
  writer_->set_mesh(m, last_step_ + 1);
  remap_monitors(monitors_, m, re.kept);
  mesh_nodes_ = m.num_nodes(), mesh_elements_ = m.num_elements();
  char line[512];
  std::snprintf(line, sizeof line,
                "remesh (%s): %lld elements, %lld nodes; volume change %.3g (%.3g taken out of the dies' corners "
                "and put back on the free surface), strain integral change %.3g, largest strain change %.3g",
                why.c_str(), (long long)m.num_elements(), (long long)m.num_nodes(), c.volume, re.overlap_restored,
                c.strain_integral, c.strain_max);
  std::string text = line;
  // The mesher's fallback: finer than asked, its outline's edges halved;
  // the next remeshes' simplification drops those midpoints only within
  // remesh.volume_tolerance (docs/decisions.md, "Remeshing").
  for (const std::string& b : re.subdivided)
    text += "; body '" + b + "' subdivided: gmsh's Blossom left a triangle at every size tried, the outline's edges halved";
  write_events(last_step_, last_.time, {text});
  toml::array subdivided;
  for (const std::string& b : re.subdivided) subdivided.push_back(b);
  remeshes_.push_back(toml::table{{"step", last_step_},
                                  {"stroke_mm", last_.stroke},
                                  {"reason", why},
                                  {"elements", m.num_elements()},
                                  {"nodes", m.num_nodes()},
                                  {"volume_change", c.volume},
                                  {"volume_restored", re.overlap_restored},
                                  {"strain_integral_change", c.strain_integral},
                                  {"strain_max_change", c.strain_max},
                                  {"subdivided", subdivided}});
  summary_.insert_or_assign("remeshes", remeshes_);
  jump_pending_ = true;
  if (!quiet_) std::printf("  step %5d  %s\n", last_step_, text.c_str());
}

void RunObserver::on_resumed(const StepRecord& r) {
  if (remeshes_.empty() || r.step != last_step_) return;
  // The strain-rate error estimate at the remesh's configuration on the
  // old mesh and on the new one (remesh.target_error aims at the latter).
  remeshes_.back().as_table()->insert_or_assign("strain_rate_error_before", last_.strain_rate_error_relative);
  remeshes_.back().as_table()->insert_or_assign("strain_rate_error_after", r.strain_rate_error_relative);
  summary_.insert_or_assign("remeshes", remeshes_);
  if (r.loads.empty() || last_.loads.empty()) return;
  const std::size_t k = press_load();
  const Vec2 before = last_.loads[k];
  // Signed: positive where the new mesh carries the larger load.
  const double size = before.norm() > 0 ? (r.loads[k] - before).norm() / before.norm() : r.loads[k].norm();
  const double change = r.loads[k].norm() < before.norm() ? -size : size;
  remeshes_.back().as_table()->insert_or_assign("load_jump", change);
  summary_.insert_or_assign("remeshes", remeshes_);
  char text[160];
  std::snprintf(text, sizeof text, "remesh load jump %.6g (same configuration: %.6g kN on the new mesh, %.6g on the old)",
                change, r.loads[k].norm() / 1e3, before.norm() / 1e3);
  write_events(r.step, r.time, {text});
  // What the new mesh's first solve met (contact taken over, touches).
  write_events(r.step, r.time, r.events);
}

void RunObserver::on_retry(int step, double dt, const std::string& why) {
  if (!quiet_) std::printf("  step %5d  retry with dt %.3g s: %s\n", step, dt, why.c_str());
  // The log keeps every failed attempt's reason (a run slowed by halvings
  // says why).
  std::ostringstream line;
  line << "retry with dt " << dt << " s: " << why;
  write_events(step, last_.time, {line.str()}, true);
}

void RunObserver::on_discarded(int step, const std::vector<std::string>& events) {
  write_events(step, last_.time, events, true);
}

void RunObserver::write_events(int step, double time, const std::vector<std::string>& events, bool failed) const {
  if (events.empty()) return;
  std::ofstream ev(events_path_, std::ios::app);
  for (const auto& e : events) ev << step << "," << time << "," << (failed ? "failed" : "kept") << "," << e << "\n";
}

void RunObserver::write_summary() {
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  summary_.insert_or_assign("wall_time_s", wall);
  summary_.insert_or_assign("steps", last_step_);
  // Wall time over the finished steps (the first solve at the initial
  // configuration included): what a formulation costs per step.
  if (last_step_ > 0) summary_.insert_or_assign("time_per_step_s", wall / last_step_);
  write_text_atomically(dir_ + "/summary.json", to_json(summary_) + "\n");
}

std::string RunObserver::final_loads_text() const {
  std::string text;
  for (std::size_t i = 0; i < load_names_.size() && i < last_.loads.size(); ++i) {
    const Vec2& F = last_.loads[i];
    const bool y = std::abs(F(1)) >= std::abs(F(0));
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%s.F%c %.4g kN", text.empty() ? "" : ", ", load_names_[i].c_str(), y ? 'y' : 'x',
                  1e-3 * (y ? F(1) : F(0)));
    text += buf;
  }
  return text;
}

std::string RunObserver::finish(const RunOutcome& out) {
  if (last_field_step_ != last_step_ && last_.x.size()) {
    writer_->write_step(fields(last_));
  }
  summary_.insert_or_assign("status", out.finished ? "finished" : out.interrupted ? "interrupted" : "stopped");
  if (const std::string gmsh = gmsh_module_path(); !gmsh.empty()) summary_.insert_or_assign("gmsh_module", gmsh);
  if (!out.finished) summary_.insert_or_assign("reason", out.reason);
  summary_.insert_or_assign("total_newton_iterations", out.total_newton_iterations);
  summary_.insert_or_assign("discarded_newton_iterations", out.discarded_newton_iterations);
  summary_.insert_or_assign("total_step_cuts", out.total_cuts);
  if (scene_.stepping.tolerance > 0) summary_.insert_or_assign("total_step_rejections", out.step_rejections);
  summary_.insert_or_assign("total_contact_retunes", out.retunes);
  summary_.insert_or_assign("final_stroke_mm", last_.stroke);
  summary_.insert_or_assign("final_mesh", toml::table{{"nodes", mesh_nodes_}, {"elements", mesh_elements_}});
  toml::table loads;
  for (std::size_t i = 0; i < load_names_.size() && i < last_.loads.size(); ++i)
    loads.insert(load_names_[i], pair(last_.loads[i]));
  summary_.insert_or_assign("final_load_N", loads);
  summary_.insert_or_assign("final_volume_change", initial_volume_ > 0 ? last_.volume / initial_volume_ - 1 : 0.0);
  summary_.insert_or_assign("max_abs_volume_change", max_volume_change_);
  summary_.insert_or_assign("min_scaled_jacobian", min_quality_);
  summary_.insert_or_assign(
      "timings_s", toml::table{{"assembly", out.assembly_seconds},
                               {"residual", out.residual_seconds},
                               {"contact", out.contact_seconds},
                               {"symbolic_analysis", out.analyze_seconds},
                               {"factorization", out.factor_seconds},
                               {"triangular_solves", out.solve_seconds}});
  summary_.insert_or_assign("linear_solver", toml::table{{"pattern_builds", out.pattern_builds},
                                                          {"tangent_passes", out.tangent_passes},
                                                          {"tangents_from_trials", out.tangents_from_trials},
                                                          {"force_passes", out.force_passes},
                                                          {"force_passes_reused", out.force_passes_reused},
                                                          {"factorizations", out.factorizations},
                                                          {"cholesky_fallbacks", out.cholesky_fallbacks},
                                                          {"by_cholmod", out.by_cholmod},
                                                          {"by_klu", out.by_klu},
                                                          {"by_umfpack", out.by_umfpack}});
  if (std::isfinite(out.min_tangent_rcond)) summary_.insert_or_assign("min_tangent_rcond", out.min_tangent_rcond);
  toml::array warnings;
  for (const auto& w : out.warnings) warnings.push_back(w);
  summary_.insert_or_assign("warnings", warnings);
  write_summary();
  const std::string json = to_json(summary_);
  writer_->update_metadata(json);
  return json;
}

}  // namespace rpfem
