// The run driver's observer: writes every recorded step (result.h5,
// result.xdmf, history.csv, summary.json) and prints progress.
#pragma once
#include <chrono>
#include <deque>
#include <memory>
#include <string>

#include <toml++/toml.h>

#include "app/interrupt.hpp"
#include "io/monitors.hpp"
#include "io/result_writer.hpp"
#include "model/remesh.hpp"
#include "model/scene.hpp"
#include "model/stepper.hpp"

namespace rpfem {

class RunObserver final : public StepObserver {
 public:
  RunObserver(const Scene& scene, const std::string& dir, toml::table summary, bool quiet,
              std::vector<Monitor> monitors = {});
  void on_start(const DerivedParameters& d, const std::vector<std::string>& load_names,
                const std::vector<std::string>& report_names) override;
  void on_step(const StepRecord& r) override;
  void on_retry(int step, double dt, const std::string& why) override;
  void on_discarded(int step, const std::vector<std::string>& events) override;
  // After a remesh: the load on the new mesh at the configuration of the
  // remesh against the load recorded there on the old mesh (the remesh's
  // own load change, no stroke between them).
  void on_resumed(const StepRecord& r) override;
  // A remesh after the last recorded step: the new mesh in result.h5 from
  // the next step on, the monitors on it, an event and a summary entry;
  // the load's jump is measured at the next step (against the line through
  // the two steps before the remesh).
  void remeshed(const RemeshedScene& re, const std::string& why, const RemeshChange& change);
  // The nodes the monitors follow (x_near, y_near): a remesh keeps them.
  std::vector<Index> pinned_nodes() const;
  // Completes summary.json with the outcome; returns its text.
  std::string finish(const RunOutcome& out);
  // The last recorded step's loads, "name Fx/Fy kN" for the run's last
  // line (the larger component of each, kN).
  std::string final_loads_text() const;
  bool stop_requested() const override { return interrupt_signal() != 0; }
  const std::string& dir() const { return dir_; }

 private:
  void write_summary();
  // Lines of events.csv at (step, time): `kept` for the run's record,
  // `failed` for an attempt at a step that was not kept.
  void write_events(int step, double time, const std::vector<std::string>& events, bool failed = false) const;
  // A step's record as result.h5 takes it: fields, loads and monitors, the
  // dies' profiles at its time.
  StepFields fields(const StepRecord& r) const;
  // The press load's index in a step's loads: the stroke's reference
  // (stepping.reference) where it has one, else the largest at the last
  // step. A remesh's jump is measured on it.
  std::size_t press_load() const;

  const Scene& scene_;
  std::string dir_;
  toml::table summary_;
  bool quiet_;
  std::unique_ptr<ResultWriter> writer_;
  std::unique_ptr<HistoryWriter> history_;
  std::string events_path_;
  std::vector<std::string> load_names_;
  std::vector<Monitor> monitors_;
  std::chrono::steady_clock::time_point t0_;
  double initial_volume_ = 0, max_volume_change_ = 0, min_quality_ = 1;
  int last_field_step_ = -1, expected_steps_ = 1, last_step_ = 0;
  StepRecord last_;
  // The last four recorded steps, for the trend a remesh's next step is
  // measured against.
  struct Recent {
    double stroke = 0, load = 0;  // mm, |press load| N
    bool landed = false;          // StepRecord::landing
  };
  std::deque<Recent> recent_;
  toml::array remeshes_;
  bool jump_pending_ = false;
  Index mesh_nodes_ = 0, mesh_elements_ = 0;
  double die_sagitta_ = 0;  // mm: how far a drawn die's chord may stray from its arc  // the current mesh's (summary's final_mesh)
};

}  // namespace rpfem
