#include "model/stepper.hpp"

#include <algorithm>
#include <any>
#include <cmath>
#include <stdexcept>

#include "core/sci.hpp"
#include "core/timing.hpp"
#include "mesh/error_indicator.hpp"
#include "mesh/quality.hpp"
#include "model/boundary.hpp"
#include "model/die_interference.hpp"
#include "model/run_health.hpp"
#include "model/step_control.hpp"
#include "model/step_problem.hpp"

namespace rpfem {

namespace {

// What the tangent's condition says about a failed solve: its least
// estimate, and that double precision ran out when the estimate is below
// kIllConditionedRcond or Newton stalled at its round-off floor.
std::string conditioning_note(double rcond, bool stalled) {
  if (!std::isfinite(rcond)) return "";  // nothing factorized (an own solver, an inversion)
  if (rcond >= kIllConditionedRcond && !stalled) return " (least tangent rcond " + sci(rcond) + ")";
  return "; the tangent is ill-conditioned (rcond " + sci(rcond) +
         (rcond < kIllConditionedRcond ? ", below 100 x machine epsilon" : "") +
         "): a penalty or stiffness too large for double precision; lower formulations.penalty.beta_factor, "
         "solver.alpha (or a body's material.alpha) or the stiffness contrast between bodies";
}

// Rigid zones (solver.limit_strain_rate): below the limiting rate the
// material is linear-viscous with the viscosity sigma / epsdot_lim, so a
// small limit makes the functional nearly non-smooth where the flow stops
// (1e-9 of the reference rate: 1e9 times the plastic viscosity), and
// Newton's convergence region shrinks with it: it failed at the first
// solve at 1e-6 on upsetting with m = 1, at 1e-9 on Test II. A failed
// solve below this limit (relative, the default) is therefore redone from
// the same start with the limiting rate lowered from it a decade per
// solve to the scene's, each solve warm-started from the last (as the
// friction smoothing's continuation, formulations' a): 7 solves of 6 to
// 15 iterations at 1e-9 on Test II's first step.
constexpr double kContinuationStart = 1e-3;

// The least force scale of a residual (StepProblem::set_force_floor),
// relative to the softest body's initial flow stress times the reference
// length squared: Test II's 30 N against its 0.18 kN at the first touch
// and 1e5 N later.
constexpr double kForceFloor = 1e-3;

// How often a step is redone shorter for a contact row that ended it too
// deep (ContactFormulation::overshoot). The fraction is exact for a gap
// closing at a constant rate; a second redo is a row whose rate changes
// within the step.
constexpr int kLandingRedos = 3;

struct State {
  std::vector<Vec2> x;
  std::vector<std::array<double, 4>> strain;  // at the 2x2 points
  double time = 0, stroke = 0;
};

struct Solution {
  std::vector<Vec2> v, F;
  std::vector<std::array<double, 4>> rate;  // effective strain rate at the 2x2 points
  std::vector<ElementPost> post;
  std::vector<double> flow_stress;
  int iterations = 0, passes = 0;
  int solves = 0;  // Newton (or own) solves: the passes, plus the half step's
  double residual = 0;
  double rcond = INFINITY;  // least condition estimate of the step's factorizations
  bool stalled = false;     // failed: Newton stalled at its round-off floor
  std::vector<std::string> events;
  std::string failure;  // empty when solved
};

class Runner {
 public:
  Runner(const Scene& s, ContactFormulation& c, StepObserver& o)
      : scene_(s), contact_(c), obs_(o), ws_(s.solver.linear_solver, s.solver.cholesky, s.solver.lu),
        health_({s.solver.newton.tol_force, s.penetration_tolerance, s.min_scaled_jacobian, s.remesh.enabled}) {
    ws_.threads = s.solver.threads;
  }

  RunOutcome run(const RunState* from);

 private:
  // One try of a step of length dt from st: the midpoint's half-step
  // solve, the move, the end solve. Empty on success, else why it failed.
  struct Attempt {
    State next;
    Solution sol;
    std::vector<Vec2> moved_by;
    bool factorized = false;  // a failed solve: its least rcond and whether Newton stalled
    double rcond = INFINITY;
    bool stalled = false;
    bool inverted = false;    // failed: an element inverted in the move
    double quality = 0;       // the moved configuration's least scaled Jacobian
    Index quality_element = -1;  // its element
    std::vector<std::string> events;  // the contact events of all its solves, failed or not
    double estimate = 0;              // step control: the local error estimate (model/step_control.hpp)
    int iterations = 0;               // Newton iterations of all its solves, failed or not
  };
  // Scales, materials, the run's start for the observer.
  void set_up();
  std::string attempt(const State& st, const Solution& sol, int step, double dt, Attempt& out);
  // A step from st (sol solved there), halving it on failure; false when
  // the run stops (out_.reason says why).
  bool take_step(State& st, Solution& sol, int step);
  // from: the state the velocity moves the nodes from (midpoint half step;
  // default st);
  // moves: whether it moves them at all (StepView::moves).
  Solution solve(const State& st, const std::vector<Vec2>& guess, int step, double dt, const State* from = nullptr,
                 bool moves = true, bool anticipates = true);
  // Whether a solve at a step's end (or the run's first) moves the nodes
  // over dt (StepView::moves), and whether it anticipates the landings
  // within dt (StepView::anticipates).
  bool start_moves() const { return scene_.stepping.integration != TimeIntegration::Midpoint; }
  bool start_anticipates() const;
  // One solve of the step's problem from u: the formulation's own solver,
  // or Newton (warm: a re-solve after a small change, StepCheck::warm).
  NewtonResult solve_once(const StepView& sv, StepProblem& problem, Vec& u, bool warm);
  // A failed solve whose limiting strain rate is below kContinuationStart
  // is redone by continuation (see kContinuationStart).
  NewtonResult solve_with_continuation(const StepView& sv, StepProblem& problem, Vec& u, bool warm,
                                       std::vector<std::string>& events);
  State advance(const State& st, const Solution& sol, double dt) const;
  StepView view(const State& st, int step, double dt) const;
  // quality: the configuration's least scaled Jacobian.
  // quality_element: its element (-1: not tracked).
  void record(const State& st, const Solution& sol, int step, double dt, int cuts, double quality,
              Index quality_element, bool resumed = false, bool landing = false);
  // "element E of body B" (result.h5's element numbering).
  std::string element_name(Index e) const {
    return "element " + std::to_string(e) + " of body '" + scene_.mesh.body_names[scene_.mesh.element_body[e]] + "'";
  }
  RunOutcome finish();
  const Die* find_die(const std::string& name) const {
    for (const Die& d : scene_.dies)
      if (d.name == name) return &d;
    return nullptr;
  }

  const Scene& scene_;
  ContactFormulation& contact_;
  StepObserver& obs_;
  SolverWorkspace ws_;
  KernelConstraints bc_;
  DerivedParameters derived_;
  std::vector<ElementMaterial> materials_;
  std::vector<double> flow_stress_;
  RunOutcome out_;
  RunHealth health_;  // what the recorded steps leave to warn of
  double segment_start_stroke_ = 0;  // mm: where this run started (a resume's stroke)
  int segment_first_step_ = 0;       // the step this run started at (a resume's)
  double segment_start_quality_ = 1;  // the least scaled Jacobian of its first configuration
  double last_dt_ = 0;                // s, the last recorded step's length
  // Step control (stepping.tolerance): the next step's increment (mm), the
  // recorded step's estimate and its bound.
  double proposed_increment_ = 0, step_estimate_ = 0, step_bound_ = 0;
  // The last recorded step's largest penetration over the element size,
  // at most run.penetration_tolerance (0 where the treatment measures
  // none): the reach of a corner's reflex angle that is not an inversion
  // (attempt()).
  double last_penetration_rel_ = 0;
  // The solves of a step halved after a failed attempt (or of the first
  // configuration after its solve failed; not the attempt past a landing,
  // a step of another length and not a repeat) run Newton with the
  // watchdog (solver/newton.hpp), after kRetryWatchdog iterations without
  // |R| halving: longer than the anchored merit's cycles seen (2 to 5
  // iterates on core_in_sleeve), and a first attempt's solve is never
  // changed by it.
  bool retry_ = false;
  // The attempt being solved ends at a landing (StepView::at_landing).
  bool at_landing_ = false;
  static constexpr int kRetryWatchdog = 6;
};

StepView Runner::view(const State& st, int step, double dt) const {
  StepView v;
  v.mesh = &scene_.mesh;
  v.x = &st.x;
  v.x_from = &st.x;
  v.time_from = st.time;
  v.flow_stress = &flow_stress_;
  v.geometry = scene_.geometry;
  v.time = st.time;
  v.dt = dt;
  v.step = step;
  v.at_landing = at_landing_;
  return v;
}

Solution Runner::solve(const State& st, const std::vector<Vec2>& guess, int step, double dt, const State* from,
                       bool moves, bool anticipates) {
  Solution sol;
  StepView sv = view(st, step, dt);
  if (from) sv.x_from = &from->x, sv.time_from = from->time;
  sv.moves = moves;
  sv.anticipates = anticipates;
  sv.velocity = &guess;
  const std::vector<Vec2> fext = traction_forces(scene_.mesh, st.x, scene_.geometry, scene_.tractions);
  StepProblem problem(sv, st.strain, materials_, derived_.limiting_strain_rate, fext, contact_, ws_);
  problem.set_force_floor(derived_.force_floor);
  {
    ScopedSeconds timing(ws_.contact_seconds);
    contact_.begin_step(sv);
  }
  ws_.linear.reset_rcond();
  // A failed solve keeps the least condition estimate it met (the stop
  // reason reports it).
  auto fail = [&](std::string why) {
    sol.failure = std::move(why);
    sol.rcond = ws_.linear.stats().min_rcond;
    return sol;
  };
  std::vector<Vec2> v = guess;
  const bool cold = std::all_of(guess.begin(), guess.end(), [](const Vec2& g) { return g.isZero(); });
  constexpr int kMaxPasses = 50;
  bool warm = false;  // the pass re-solves after a small change (StepCheck::warm)
  for (sol.passes = 1; sol.passes <= kMaxPasses; ++sol.passes) {
    std::vector<NodeConstraint> cons = bc_.constraints;
    {
      ScopedSeconds timing(ws_.contact_seconds);
      contact_.constraints(sv, cons);
    }
    try {
      problem.set_constraints(cons);
    } catch (const std::invalid_argument& e) {
      return fail(e.what());
    }
    Vec u = problem.dofs().reduce(v);
    if (cold && sol.passes == 1) {
      problem.viscous_predictor(derived_.reference_strain_rate, u);
      // The predictor's linear system is not the step's tangent (without a
      // formulation's constraints a body may float: ipopt's rows are not
      // in it): its condition is not recorded.
      ws_.linear.reset_rcond();
    }
    const NewtonResult r = solve_with_continuation(sv, problem, u, warm, sol.events);
    sol.iterations += r.iterations;
    sol.residual = r.residual;
    sol.stalled = r.stalled;
    if (!r.converged && contact_.fall_back()) {
      // Once more from the pass's start, the treatment's robust scheme.
      sol.events.push_back("solved again by the contact treatment's fallback after " + r.reason);
      ws_.linear.reset_rcond();  // the failed attempt's matrices are not the step's
      warm = false;
      continue;
    }
    if (!r.converged) return fail(r.reason);
    problem.dofs().expand(u, v);
    problem.nodal_forces(v, sol.F);
    StepCheck check;
    {
      ScopedSeconds timing(ws_.contact_seconds);
      check = contact_.settle(sv, v, sol.F);
    }
    sol.events.insert(sol.events.end(), check.events.begin(), check.events.end());
    warm = check.warm;
    if (!check.resolve) break;
  }
  if (sol.passes > kMaxPasses) return fail("contact state did not settle in " + std::to_string(kMaxPasses) + " passes");
  sol.v = std::move(v);
  sol.solves = sol.passes;
  sol.rcond = ws_.linear.stats().min_rcond;
  // Per element: strain rates for the strain update, recorded fields.
  const Index ne = scene_.mesh.num_elements();
  sol.rate.resize(ne);
  sol.post.resize(ne);
  sol.flow_stress.resize(ne);
  for (Index e = 0; e < ne; ++e) {
    const RigidPlasticInput in = problem.element_input(e, sol.v);
    sol.post[e] = rigid_plastic_post(in);
    sol.rate[e] = sol.post[e].strain_rate;
    double mean_strain = 0;
    for (double s : st.strain[e]) mean_strain += 0.25 * s;
    // The material's flow stress (at no less than the limiting rate, so a
    // rigid zone reports its yield stress, not the linear-viscous stress).
    const double lim = derived_.limiting_strain_rate;
    sol.flow_stress[e] = flow_point(*in.law, mean_strain, std::max(sol.post[e].strain_rate_mean, lim), lim).sigma;
    for (double r : sol.rate[e])
      if (!std::isfinite(r)) return fail("non-finite strain rate");
  }
  return sol;
}

NewtonResult Runner::solve_once(const StepView& sv, StepProblem& problem, Vec& u, bool warm) {
  if (StepSolver* own = contact_.solver()) {
    const SolveOutcome o = own->solve(sv, problem, u);
    NewtonResult r;
    r.converged = o.converged;
    r.iterations = o.iterations;
    r.residual = o.residual;
    r.reason = o.reason;
    return r;
  }
  NewtonSettings settings = scene_.solver.newton;
  if (warm) settings.direct_iterations = 0, settings.reuse_factorization = true;
  if (retry_) settings.watchdog = kRetryWatchdog;
  if (const double t = contact_.tangent().tol_velocity; t > 0) settings.tol_velocity = std::min(settings.tol_velocity, t);
  NewtonResult r = newton_solve(problem.newton_system(), settings, u);
  if (!r.converged) r.reason = "Newton: " + r.reason;
  return r;
}

NewtonResult Runner::solve_with_continuation(const StepView& sv, StepProblem& problem, Vec& u, bool warm,
                                             std::vector<std::string>& events) {
  const Vec start = u;
  NewtonResult r = solve_once(sv, problem, u, warm);
  const double lim = problem.limiting_strain_rate();
  const double first = kContinuationStart * derived_.reference_strain_rate;
  if (r.converged || !(lim < first)) return r;
  // Redone from the same start: each limiting rate a decade below the
  // last, down to the scene's, each solve starting from the last solution.
  u = start;
  int iterations = r.iterations, solves = 0;
  double rate = first;
  for (;;) {
    problem.set_limiting_strain_rate(rate);
    r = solve_once(sv, problem, u, warm);
    iterations += r.iterations, ++solves;
    if (!r.converged || rate == lim) break;
    rate = 0.1 * rate > lim * (1 + 1e-9) ? 0.1 * rate : lim;
  }
  problem.set_limiting_strain_rate(lim);
  r.iterations = iterations;
  const std::string what = "continuation of the limiting strain rate from " + sci(kContinuationStart) + " to " +
                           sci(rate / derived_.reference_strain_rate) + " of the reference rate";
  if (!r.converged) r.reason += " (by " + what + ")";
  else events.push_back("solved by " + what + " (" + std::to_string(solves) + " solves)");
  return r;
}

State Runner::advance(const State& st, const Solution& sol, double dt) const {
  State n = st;
  for (std::size_t i = 0; i < n.x.size(); ++i) n.x[i] += dt * sol.v[i];
  for (std::size_t e = 0; e < n.strain.size(); ++e)
    for (int q = 0; q < 4; ++q) n.strain[e][q] += dt * sol.rate[e][q];
  n.time += dt;
  n.stroke += dt * derived_.reference_speed;
  return n;
}

void Runner::record(const State& st, const Solution& sol, int step, double dt, int cuts, double quality,
                    Index quality_element, bool resumed, bool landing) {
  StepRecord r;
  r.step = step;
  r.time = st.time;
  r.stroke = st.stroke;
  r.dt = dt;
  r.cuts = cuts;
  r.landing = landing;
  r.newton_iterations = sol.iterations;
  r.contact_passes = sol.passes;
  r.solves = sol.solves;
  r.residual = sol.residual;
  r.tangent_rcond = std::isfinite(sol.rcond) ? sol.rcond : -1.0;
  r.step_error = resumed ? 0.0 : step_estimate_;
  r.step_error_bound = resumed ? 0.0 : step_bound_;
  const StepView sv = view(st, step, dt);
  ContactRecord cr = contact_.record(sv, sol.v, sol.F);
  // The reach of a fold's reflex corner (attempt()): this step's
  // penetration, to at most what the run accepts without a warning.
  last_penetration_rel_ = cr.penetration_rel && std::isfinite(*cr.penetration_rel)
                              ? std::min(*cr.penetration_rel, scene_.penetration_tolerance)
                              : 0.0;
  // The run's worst conditioning, residual floor, friction, penetration
  // and distortion count recorded steps only.
  if (!resumed) {
    health_.note_solve(step, sol.rcond, sol.residual);
    health_.note_contact(step, st.stroke, cr.friction_violation, cr.friction_cause, cr.penetration_rel);
    health_.note_quality(step, st.stroke, quality, quality_element);
  }
  r.x = st.x;
  r.v = sol.v;
  const Index ne = scene_.mesh.num_elements();
  r.strain_rate.resize(ne);
  r.strain.resize(ne);
  r.mean_stress.resize(ne);
  double volume = 0;
  for (Index e = 0; e < ne; ++e) {
    r.strain_rate[e] = sol.post[e].strain_rate_mean;
    r.strain[e] = 0.25 * (st.strain[e][0] + st.strain[e][1] + st.strain[e][2] + st.strain[e][3]);
    r.mean_stress[e] = sol.post[e].mean_stress;
    volume += sol.post[e].volume;
    for (double rate : sol.rate[e]) r.rigid_points += rate < derived_.limiting_strain_rate;
  }
  r.flow_stress = sol.flow_stress;
  // The recovery-based estimate of the strain-rate error (mesh/error_indicator.hpp).
  StrainRateError zz = strain_rate_error(scene_.mesh, st.x, sol.rate, scene_.geometry);
  r.strain_rate_error = std::move(zz.element_rms);
  r.strain_rate_error_relative = zz.relative;
  r.volume = volume * bc_.volume_factor;
  r.loads = bc_.group_loads(st.x, sol.F);
  for (const Vec2& l : cr.loads) r.loads.push_back(l);
  // In axisymmetry radial nodal forces cancel around the circumference: a
  // body's resultant force has no radial component.
  if (scene_.geometry == Geometry::Axisymmetric)
    for (Vec2& l : r.loads) l(0) = 0;
  r.contact_force = std::move(cr.force);
  r.contact_report = std::move(cr.columns);
  r.node_fields = std::move(cr.fields);
  r.events = sol.events;
  r.min_scaled_jacobian = quality;
  if (resumed)
    obs_.on_resumed(r);
  else
    obs_.on_step(r);
}

RunOutcome Runner::finish() {
  out_.min_tangent_rcond = health_.min_rcond();
  for (std::string& w : health_.warnings([this](Index e) { return element_name(e); }))
    out_.warnings.push_back(std::move(w));
  const LinearSolveStats& ls = ws_.linear.stats();
  out_.assembly_seconds = ws_.assembly_seconds;
  out_.residual_seconds = ws_.residual_seconds;
  out_.contact_seconds = ws_.contact_seconds;
  out_.analyze_seconds = ls.analyze_seconds;
  out_.factor_seconds = ls.factor_seconds;
  out_.solve_seconds = ls.solve_seconds;
  out_.pattern_builds = ws_.pattern_builds;
  out_.tangent_passes = ws_.tangent_passes, out_.tangents_from_trials = ws_.tangents_from_trials;
  out_.force_passes = ws_.force_passes, out_.force_passes_reused = ws_.force_passes_reused;
  out_.factorizations = ls.factorizations;
  out_.cholesky_fallbacks = ls.cholesky_fallbacks;
  out_.by_cholmod = ls.by_cholmod, out_.by_klu = ls.by_klu, out_.by_umfpack = ls.by_umfpack;
  return out_;
}

void Runner::set_up() {
  const Mesh& mesh = scene_.mesh;
  bc_ = KernelConstraints(scene_);
  // Scales: the reference motion's speed over the bodies' size.
  const auto& ref = scene_.stepping.reference;
  if (auto s = bc_.group_speed(ref)) derived_.reference_speed = *s;
  else if (const Die* d = find_die(ref)) derived_.reference_speed = d->motion.max_speed();
  else throw InputError(scene_.file + ": key 'stepping.reference': '" + ref +
                        "' names no prescribed velocity group or die of this scene");
  if (!(derived_.reference_speed > 0))
    throw InputError(scene_.file + ": key 'stepping.reference': the reference motion '" + ref + "' has zero speed");
  derived_.reference_length = bc_.size;
  derived_.reference_strain_rate = derived_.reference_speed / derived_.reference_length;
  derived_.limiting_strain_rate = scene_.solver.limit_rate_relative * derived_.reference_strain_rate;
  derived_.regularization = scene_.solver.regularization / derived_.reference_strain_rate;
  for (const auto& b : scene_.bodies)
    derived_.alpha.push_back(b.alpha_relative.value_or(scene_.solver.alpha_relative) * b.law.yield(0.0) /
                             derived_.reference_strain_rate);
  materials_.resize(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const int b = mesh.element_body[e];
    materials_[e] = {&scene_.bodies[b].law, derived_.alpha[b], derived_.regularization};
  }
  flow_stress_.assign(mesh.num_elements(), 0.0);
  for (Index e = 0; e < mesh.num_elements(); ++e) flow_stress_[e] = materials_[e].law->yield(0.0);
  derived_.dt_nominal = scene_.stepping.stroke_increment / derived_.reference_speed;
  double softest = INFINITY;
  for (const auto& b : scene_.bodies) softest = std::min(softest, b.law.yield(0.0));
  derived_.force_floor = kForceFloor * softest * derived_.reference_length * derived_.reference_length;

  const ContactInfo info = contact_.info();
  std::vector<std::string> load_names = bc_.load_names();
  for (const auto& n : info.load_names) load_names.push_back(n);
  derived_.contact = info.derived;
  // No run starts on scales double precision cannot hold: a flow stress of
  // 1e308 MPa made alpha infinite, the first residual NaN, and
  // summary.json read "Infinity". Likewise the regularization's viscosity,
  // c = regularization sigma_y (as in fem/rigid_plastic_element.cpp).
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) {
    const BodySpec& body = scene_.bodies[b];
    if (!std::isfinite(derived_.alpha[b]) || !std::isfinite(body.law.yield(0.0)))
      throw InputError(scene_.file + ": key 'bodies." + body.name +
                       ".material': its initial flow stress gives a volumetric penalty alpha of " +
                       std::to_string(derived_.alpha[b]) +
                       " MPa s; expected a flow stress and speeds whose scales are finite in double precision");
    if (!std::isfinite(derived_.regularization * body.law.yield(0.0)))
      throw InputError(scene_.file + ": key 'solver.regularization': with body '" + body.name +
                       "' its viscosity is not finite in double precision; expected a regularization whose product "
                       "with the flow stress over the reference strain rate is finite");
  }
  const std::vector<NamedValue> scales = {{"reference strain rate (1/s)", derived_.reference_strain_rate},
                                          {"nominal step (s)", derived_.dt_nominal},
                                          {"force scale (N)", derived_.force_floor}};
  std::vector<NamedValue> all = scales;
  all.insert(all.end(), info.derived.begin(), info.derived.end());
  for (const auto& d : all)
    if (!std::isfinite(d.value))
      throw InputError(scene_.file + ": the run's " + d.name + " is " + std::to_string(d.value) +
                       "; expected finite scales (check the materials' flow stress, the speeds and the sizes)");
  obs_.on_start(derived_, load_names, info.column_names);
}

bool Runner::start_anticipates() const {
  // Under `midpoint` the end solve only records and predicts the next half
  // step (it does not move the nodes). Under Euler its velocity moves them
  // over the next step: with fixed steps as long as this one (dt), whose
  // landings it anticipates. Under step control the next step's length is
  // chosen after this solve (the controller's proposal, a rejection's cut),
  // so an anticipation over this step's dt is of another step: a node
  // still open that closes within dt was pressed already (its force in
  // the recorded load) and, in contact, was not one landing control ends a
  // step at, while the next step, shorter, found it open and let it go
  // (Test II's die under ssn at 1e-3: the punch's nodes touched and let go
  // 2 to 4 times each, 32 steps to 2 mm kept at the least increment;
  // docs/decisions.md, "Landing control"). There only the nodes touching
  // now take part, and landing control ends the next step where its
  // velocity lands another.
  return !(start_moves() && scene_.stepping.tolerance > 0 && contact_.controls_landings());
}

std::string Runner::attempt(const State& st, const Solution& sol, int step, double dt, Attempt& out) {
  // In the midpoint scheme the velocity at the half step moves the nodes
  // (second order in dt); the solves at the start and end of a step only
  // predict and record.
  const bool midpoint = scene_.stepping.integration == TimeIntegration::Midpoint;
  // The step control needs the half step's velocity under either
  // integration (the embedded pair of model/step_control.hpp).
  const bool control = scene_.stepping.tolerance > 0;
  const Solution* mover = &sol;
  Solution mid;
  auto failed = [&](const Solution& f, const std::string& why) {
    out.rcond = f.rcond, out.stalled = f.stalled, out.factorized = true;
    out.iterations = f.iterations + (&f != &mid ? mid.iterations : 0);
    if (&f != &mid) out.events = mid.events;
    out.events.insert(out.events.end(), f.events.begin(), f.events.end());
    return why;
  };
  if (midpoint || control) {
    mid = solve(advance(st, sol, 0.5 * dt), sol.v, step, dt, &st);
    if (!mid.failure.empty()) return failed(mid, "midpoint solve: " + mid.failure);
    if (midpoint) mover = &mid;
    if (control)
      out.estimate = step_error_estimate(scene_.mesh, scene_.geometry, st.x, dt, sol.v, mid.v, st.strain, sol.rate,
                                         mid.rate, materials_, derived_.reference_length);
  }
  out.next = advance(st, *mover, dt);
  StepView moved = view(st, step, dt);
  moved.time = out.next.time;
  moved.x = moved.x_from = &out.next.x;
  moved.time_from = out.next.time;
  contact_.place_on_surfaces(moved, out.next.x);
  const MeshQuality mq = mesh_quality(scene_.mesh, out.next.x);
  const double q = out.quality = mq.min_scaled_jacobian;
  out.quality_element = mq.worst_jacobian_element;
  // A corner angle of exactly 180 degrees (scaled Jacobian 0) is not an
  // inversion: it is what a side node folding over onto a flat die makes of
  // its element's corner (the element stays integrable); only a reflex
  // corner beyond round-off is. Where the enforcement lets nodes penetrate
  // (a penalty's gap), the three nodes of such a corner lie on the die to
  // within that penetration d, and the corner's angle is 180 degrees to
  // within about 2 d / h (the scaled Jacobian of a corner is the sine of
  // its angle): a reflex angle within that reach is the same fold, not an
  // inversion.
  // An element inverted at a Gauss point (det J <= 0 where its stiffness
  // is integrated) is inverted whatever its corners say.
  constexpr double kReflexTolerance = 1e-9;
  if (!(mq.min_gauss_jacobian > 0)) {
    out.inverted = true;
    out.events = mid.events;
    out.iterations = mid.iterations;
    return element_name(mq.worst_gauss_element) + " inverts at a Gauss point (Jacobian determinant " +
           sci(mq.min_gauss_jacobian) + " mm^2; min scaled Jacobian " + sci(q) + ")";
  }
  if (!(q > -std::max(kReflexTolerance, 2 * last_penetration_rel_))) {
    out.inverted = true;
    out.events = mid.events;
    out.iterations = mid.iterations;
    return element_name(mq.worst_jacobian_element) + " inverts (min scaled Jacobian " + sci(q) + ")";
  }
  out.sol = solve(out.next, mover->v, step, dt, nullptr, start_moves(), start_anticipates());
  if (!out.sol.failure.empty()) return failed(out.sol, out.sol.failure);
  out.moved_by = mover->v;
  // Contact events found by the half-step solve belong to this step.
  out.sol.events.insert(out.sol.events.begin(), mid.events.begin(), mid.events.end());
  out.events = out.sol.events;
  out.sol.iterations += mid.iterations;
  out.sol.solves += mid.solves;
  out.iterations = out.sol.iterations;
  return "";
}

bool Runner::take_step(State& st, Solution& sol, int step) {
  const SteppingSpec& sp = scene_.stepping;
  const double end = sp.end_stroke;
  const bool control = sp.tolerance > 0;
  const double increment = control ? proposed_increment_ : sp.increment_at(st.stroke);
  double dt = std::min(increment, end - st.stroke) / derived_.reference_speed;
  const std::optional<double> lim = contact_.limit_dt(view(st, step, dt), sol.v);
  const bool to_landing = lim && *lim < dt;
  const double nominal_dt = dt;
  if (to_landing) dt = *lim;
  const double landing_dt = dt;
  bool past_landing = false;  // the step retried past its landing (below)
  Attempt a;
  int cuts = 0, redone = 0;
  bool landed = to_landing;
  bool rejected = false;  // step control: redone shorter for its estimate
  contact_.remember_start_gaps();
  // An attempt that is not kept leaves the contact state as the step
  // started (a retry starts from it, not from what the failed attempt
  // settled); its events are reported as a failed attempt's.
  const std::any start_state = contact_.save_state();
  const auto discard = [&] {
    out_.discarded_newton_iterations += a.iterations;
    obs_.on_discarded(step, a.events);
    contact_.restore_state(start_state);
  };
  for (;;) {
    a = Attempt{};
    retry_ = cuts > 0;
    at_landing_ = landed;
    std::string why = attempt(st, sol, step, dt, a);
    retry_ = at_landing_ = false;
    // A step that takes the least scaled Jacobian below the floor counts as
    // failed where the run remeshes.
    const bool poor = why.empty() && scene_.remesh.enabled && a.quality < scene_.remesh.reject_below;
    if (poor) why = "least scaled Jacobian " + sci(a.quality) + " below remesh.reject_below";
    // The treatment changed its parameters for the step (a penalty raised
    // where a row ended deeper than run.penetration_tolerance): solved
    // again from the step's start, same length. The treatment bounds how
    // often (contact/adaptive_penalty.hpp). Before the landing redo below:
    // a raise is kept for the steps after, a shorter step is not.
    if (why.empty()) {
      if (const std::optional<std::string> t = contact_.retune()) {
        ++out_.retunes;
        discard();  // the raise itself is kept (the treatment's own, not the step's state)
        obs_.on_retry(step, dt, *t);
        continue;
      }
    }
    // A row that ended the step deeper than its enforcement saw: the step
    // redone shorter (to a landing, for a row open at the start), a few
    // times at most, not counted as a halving. A fraction below the
    // smallest step a halving would leave is not taken.
    if (why.empty() && redone < kLandingRedos) {
      const std::optional<double> t = contact_.overshoot();
      if (t && *t > std::ldexp(1.0, -scene_.stepping.max_cuts)) {
        ++redone, landed = true;
        discard();
        obs_.on_retry(step, *t * dt, "a contact row ends the step too deep; redone to " + sci(*t) + " of it");
        dt *= *t;
        continue;
      }
    }
    // Step control: a step whose estimate exceeds its bound is redone from
    // its start with the increment (2) of model/step_control.hpp, down to
    // stepping.min_increment; there it is kept (and counted for the
    // warning).
    if (why.empty() && control) {
      const double ds = dt * derived_.reference_speed;
      const double bound = step_error_bound(sp.tolerance, ds, end);
      if (a.estimate > bound && ds > sp.min_increment * (1 + 1e-9)) {
        const double next = std::max(sp.min_increment, next_increment(ds, a.estimate, bound, ds, true));
        ++out_.step_rejections;
        rejected = true, landed = false;
        discard();
        obs_.on_retry(
            step, next / derived_.reference_speed,
            "local error estimate " + sci(a.estimate) + " above its bound " + sci(bound) + " (stepping.tolerance)");
        dt = next / derived_.reference_speed;
        continue;
      }
    }
    if (why.empty()) break;
    if (scene_.remesh.enabled && (a.inverted || poor) && step > segment_first_step_ + 1) {
      // Remesh the last configuration rather than creep up to the fold.
      out_.remesh = "step " + std::to_string(step) + ": " + why;
      discard();
      return false;
    }
    // A fresh mesh (the run's first, or a remesh's) whose first step falls
    // below the floor: halved like a failing step, the last halving taken.
    if (poor && cuts == scene_.stepping.max_cuts) break;
    // A step that failed ending at a landing is tried once at its length
    // without the landing, the node landing within it and ending the step
    // pressing. At the landing the row ends at zero gap and zero force, on
    // both sides of its contact condition at once; an enforcement that
    // cannot settle it there fails, and halvings leave the same landing to
    // the next step, ended at it again (the remeshed ring at m = 1 under
    // ssn: 13 failed attempts of 40 Newton iterations a landing, the step
    // halved each time down to 2e-6 mm). If that fails too, the halvings
    // go on from the landing. A solve's failure only: a longer step
    // distorts the mesh further.
    if (to_landing && cuts == 0 && !past_landing && !poor && !a.inverted) {
      discard();
      past_landing = true, landed = false;
      obs_.on_retry(step, nominal_dt, why + "; tried again past the landing it ended at");
      dt = nominal_dt;
      continue;
    }
    if (cuts == scene_.stepping.max_cuts) {
      out_.reason = "step " + std::to_string(step) + " at stroke " + std::to_string(st.stroke) + " mm failed after " +
                    std::to_string(cuts) + " step halvings: " + why +
                    (a.factorized ? conditioning_note(a.rcond, a.stalled) : std::string());
      // Without remeshing an inverted element ends the run: the mesh is too
      // distorted to go on (the remesher would mesh the last configuration
      // anew).
      if (a.inverted && !scene_.remesh.enabled)
        out_.reason += "; the mesh is too distorted to go on: remesh it (a [remesh] table with enabled = true)";
      discard();
      return false;
    }
    discard();
    if (past_landing && cuts == 0) dt = landing_dt;
    obs_.on_retry(step, 0.5 * dt, why);
    dt *= 0.5;
    ++cuts;
    landed = false;  // a halved step ends short of the landing
  }
  if (control) {
    // The next increment from this step's estimate (2). A step ended short
    // of the proposed increment by a landing or the end of the stroke (not
    // by the control or a failure) changes the proposal from the proposal.
    const double ds = dt * derived_.reference_speed;
    const double bound = step_error_bound(sp.tolerance, ds, end);
    const double base = rejected || cuts > 0 ? ds : std::max(ds, proposed_increment_);
    proposed_increment_ =
        std::clamp(next_increment(ds, a.estimate, bound, base, false), sp.min_increment, sp.max_increment);
    step_estimate_ = a.estimate, step_bound_ = bound;
    health_.note_step_error(step, a.estimate, bound);
  }
  contact_.end_step(view(st, step, dt), a.moved_by);
  st = std::move(a.next);
  sol = std::move(a.sol);
  flow_stress_ = sol.flow_stress;
  out_.total_newton_iterations += sol.iterations;
  out_.total_cuts += cuts;
  out_.steps = step;
  record(st, sol, step, dt, cuts, a.quality, a.quality_element, false, landed);
  last_dt_ = dt;
  // Remesh triggers (not at the end of the stroke).
  const RemeshSpec& rm = scene_.remesh;
  const double eps = 1e-9 * std::max(scene_.stepping.end_stroke, 1.0);
  if (rm.enabled && st.stroke < scene_.stepping.end_stroke - eps) {
    // A fresh mesh whose own worst element is below the threshold (gmsh's
    // quads near a sharp outline corner) is remeshed once that element has
    // lost a fifth of its quality, not after every step.
    if (a.quality < std::min(rm.min_scaled_jacobian, 0.8 * segment_start_quality_))
      out_.remesh = "least scaled Jacobian " + sci(a.quality) + " below remesh.min_scaled_jacobian";
    else if (rm.stroke_interval > 0 && st.stroke >= segment_start_stroke_ + rm.stroke_interval - eps)
      out_.remesh = "remesh.stroke_interval reached";
    else if (rm.die_interference > 0) {
      const DieInterference d = die_interference(scene_, st.x, st.time);
      if (d.relative > rm.die_interference)
        out_.remesh = "die '" + scene_.dies[d.die].name + "' " + sci(d.depth) + " mm into body '" +
                      scene_.mesh.body_names[d.body] + "', " + sci(d.relative) +
                      " of the element size there, above remesh.die_interference";
    }
    if (!out_.remesh.empty()) return false;
  }
  return true;
}

RunOutcome Runner::run(const RunState* from) {
  set_up();
  State st;
  st.x = scene_.mesh.x;
  st.strain.assign(scene_.mesh.num_elements(), {0, 0, 0, 0});
  std::vector<Vec2> guess(st.x.size(), Vec2::Zero());
  if (from) {
    if (from->x.size() != st.x.size() || from->strain.size() != st.strain.size())
      throw std::invalid_argument("run_scene: the state to resume from is not on the scene's mesh");
    st.x = from->x, st.strain = from->strain, st.time = from->time, st.stroke = from->stroke;
    segment_start_stroke_ = from->stroke;
    segment_first_step_ = from->step;
    if (from->v.size() == guess.size()) guess = from->v;
    // The flow stress at the start: the law at the state's strain.
    for (Index e = 0; e < scene_.mesh.num_elements(); ++e) {
      double mean = 0;
      for (double q : st.strain[e]) mean += 0.25 * q;
      flow_stress_[e] = materials_[e].law->yield(mean);
    }
  }
  // A resumed run solves its first configuration with the step that led
  // there (a contact penalty on the predicted gap depends on it), so the
  // solve repeats the recorded one on the new mesh.
  last_dt_ = from && from->dt > 0 ? from->dt : derived_.dt_nominal;
  // The step control's first increment: stroke_increment, or on resuming
  // the last step's.
  proposed_increment_ = from && from->dt > 0 ? from->dt * derived_.reference_speed : scene_.stepping.stroke_increment;
  if (scene_.stepping.tolerance > 0)
    proposed_increment_ = std::clamp(proposed_increment_, scene_.stepping.min_increment, scene_.stepping.max_increment);
  const int first = segment_first_step_;
  const std::any initial_state = contact_.save_state();
  Solution sol = solve(st, guess, first, last_dt_, nullptr, start_moves(), start_anticipates());
  // A failed first solve tried again from the contact state it started
  // with (from `start`, with the retries' watchdog if `watchdog`); kept,
  // with `note` on its events, where it converges.
  const auto again = [&](const std::vector<Vec2>& start, bool watchdog, const std::string& note) {
    const std::string why = sol.failure;
    contact_.restore_state(initial_state);
    retry_ = watchdog;
    Solution s = solve(st, start, first, last_dt_, nullptr, start_moves(), start_anticipates());
    retry_ = false;
    if (!s.failure.empty()) return;
    sol = std::move(s);
    sol.events.insert(sol.events.begin(), note + " (" + why + ")");
  };
  // A resumed solve from the velocities carried over from the old mesh
  // may fail where one from rest does not (they break the new mesh's
  // linearized contact constraints: Ipopt's restoration phase failed on the
  // backward extrusion at 6 mm); it is tried again from rest.
  if (from && !sol.failure.empty() && from->v.size() == guess.size())
    again(std::vector<Vec2>(st.x.size(), Vec2::Zero()), false,
          "resumed solve from the carried-over velocities failed: solved from rest");
  // Failed still: once more from the same start under the retries' watchdog.
  if (!sol.failure.empty()) again(guess, true, "first solve failed: solved again with Newton's watchdog");
  if (!sol.failure.empty()) {
    out_.reason = "step " + std::to_string(first) + (from ? " (resumed)" : " (initial configuration)") + ": " +
                  sol.failure + conditioning_note(sol.rcond, sol.stalled);
    return finish();
  }
  flow_stress_ = sol.flow_stress;
  // A resumed run's first solve starts it: the step it resumes at is on
  // record already (on its old mesh, after a remesh), so the observer
  // sees it apart (on_resumed).
  const MeshQuality start_quality = mesh_quality(scene_.mesh, st.x);
  segment_start_quality_ = start_quality.min_scaled_jacobian;
  record(st, sol, first, from ? last_dt_ : 0.0, 0, segment_start_quality_, start_quality.worst_jacobian_element,
         from != nullptr);
  out_.total_newton_iterations += sol.iterations;
  const double end = scene_.stepping.end_stroke;
  const double eps = 1e-9 * std::max(end, 1.0);
  // The last accepted state, where a run goes on from: take_step leaves st
  // and sol there when it stops, and out_.steps at its step (recorded, or
  // the one resumed at).
  const auto stop = [&] {
    out_.last = RunState{st.x, st.strain, sol.v, st.time, st.stroke, std::max(first, out_.steps), last_dt_, sol.rate};
    return finish();
  };
  for (int step = first + 1; st.stroke < end - eps; ++step) {
    if (obs_.stop_requested()) {
      out_.interrupted = true;
      out_.reason = "interrupted after step " + std::to_string(step - 1);
      return stop();
    }
    if (!take_step(st, sol, step)) return stop();
  }
  out_.finished = true;
  return stop();
}

}  // namespace

RunOutcome run_scene(const Scene& scene, ContactFormulation& contact, StepObserver& observer, const RunState* from) {
  return Runner(scene, contact, observer).run(from);
}

}  // namespace rpfem
