#include "ipopt/ipopt_step_solver.hpp"

#include <cmath>
#include <cstdio>

#include "model/step_problem.hpp"

namespace rpfem {

namespace {

// Kuhn-Tucker residuals (as checked after each solve) that make Ipopt's
// "acceptable" point a solution: penetration per element size, and the
// dual, complementarity and stationarity residuals.
constexpr double kAcceptPrimal = 1e-9;
constexpr double kAcceptKkt = 1e-8;
// Ipopt's complementarity tolerance as a fraction of kAcceptKkt (in the
// checked measure's units).
constexpr double kComplTolFactor = 0.1;
// A relative Kuhn-Tucker residual within this multiple of the residual's
// own round-off (Kkt::round_off, a one-sample estimate) is round-off.
constexpr double kRoundOffMultiple = 10;
// Ipopt's default initial barrier parameter, for the run's cold first solve.
constexpr double kColdMuInit = 0.1;

}  // namespace

IpoptStepSolver::IpoptStepSolver(const Scene& scene, CaseSection& settings, double force_scale)
    : force_scale_(std::max(force_scale, 1e-12)) {
  tol_ = settings.real("tol", 1e-10, Range::positive(), "Ipopt's tol (scaled NLP error)");
  warm_tol_ = settings.real("warm_tol", 1e-11, Range::positive(),
                            "Ipopt's tol when starting from the last multipliers (a pass near the friction bounds' "
                            "fixed point, a step's first solve)");
  loose_tol_ = settings.real("loose_tol", 1e-8, Range::positive(),
                             "Ipopt's tol for a warm pass whose solution only gives the next friction bounds");
  const double relax =
      settings.real("bound_relax_factor", 1e-10, Range::nonnegative(), "Ipopt's relaxation of the contact bounds");
  max_iter_ = settings.integer("max_iter", 500, 1, 100000);
  const std::string mu_strategy = settings.text("mu_strategy", "monotone", {"monotone", "adaptive"});
  const std::string linear_solver = settings.text("linear_solver", "mumps", {"mumps"});
  const int print_level = settings.integer("print_level", 0, 0, 12);
  // MUMPS's scaling of the augmented system: Ipopt's default (77, MUMPS's
  // automatic choice) computes one at every factorization; the system is
  // scaled by the program's own scaling already (get_scaling_parameters).
  const int mumps_scaling = settings.integer("mumps_scaling", 0, -2, 77);
  // MUMPS's maximum transversal before its ordering (ICNTL(6)): none, so
  // the analysis reads the pattern alone and a program's friction passes
  // factor on its first solve's (reuse_mumps_analysis,
  // mumps_analysis_reuse.hpp). Ipopt's default 7 (MUMPS's automatic
  // choice) permutes by the first matrix's values at every solve.
  const int mumps_permuting_scaling = settings.integer("mumps_permuting_scaling", 0, 0, 7);
  reuse_analysis_ = settings.flag("reuse_mumps_analysis", true);
  // Refinement steps on the primal-dual system before its residual is
  // checked: Ipopt's default 1 costs a back-solve at every iteration; it
  // refines anyway while the residual ratio exceeds its residual_ratio_max.
  const int min_refinement = settings.integer("min_refinement_steps", 0, 0, 10);
  mu_init_ = settings.real("mu_init", 1e-6, Range::positive(), "Ipopt's initial barrier parameter (warm starts)");
  warm_start_ = settings.flag("warm_start", true);
  warm_mu_init_ = settings.real("warm_mu_init", 1e-11, Range::positive(),
                                "Ipopt's initial barrier parameter when starting from the last multipliers");
  warm_push_ = settings.real("warm_bound_push", 1e-6, Range::positive(),
                             "Ipopt's warm_start bound, slack and multiplier pushes");
  warm_max_iter_ = settings.integer("warm_max_iter", 15, 1, 100000);
  speed_scale_ = scene.largest_speed();
  if (!(speed_scale_ > 0))
    throw InputError(scene.file + ": enforcement 'ipopt' scales by the largest prescribed speed, but nothing moves");
  round_off_force_ = scene.solver.newton.tol_force;
  secant_after_cut_ = scene.solver.newton.secant_after_cut;
  // One application for the run: its options are read once, each step
  // hands it a new NLP (a step's passes re-solve the same one).
  app_ = IpoptApplicationFactory();
  auto& o = *app_->Options();
  o.SetStringValue("sb", "yes");
  o.SetIntegerValue("print_level", print_level);
  o.SetNumericValue("tol", tol_);
  o.SetNumericValue("bound_relax_factor", relax);
  o.SetIntegerValue("max_iter", max_iter_);
  o.SetStringValue("mu_strategy", mu_strategy);
  o.SetNumericValue("mu_init", mu_init_);
  o.SetStringValue("linear_solver", linear_solver);
  o.SetIntegerValue("mumps_scaling", mumps_scaling);
  o.SetIntegerValue("mumps_permuting_scaling", mumps_permuting_scaling);
  o.SetIntegerValue("min_refinement_steps", min_refinement);
  // Read by Ipopt only with warm_start_init_point (solve()).
  o.SetNumericValue("warm_start_bound_push", warm_push_);
  o.SetNumericValue("warm_start_slack_bound_push", warm_push_);
  o.SetNumericValue("warm_start_mult_bound_push", warm_push_);
  o.SetStringValue("jac_d_constant", "yes");
  o.SetStringValue("nlp_scaling_method", "user-scaling");
  if (app_->Initialize() != Ipopt::Solve_Succeeded)
    throw InputError(scene.file + ": [formulations.ipopt]: Ipopt refused the options");
  analyses_at_start_ = mumps_analysis_counts();
}

MumpsAnalysisCounts IpoptStepSolver::mumps_analyses() const {
  const MumpsAnalysisCounts now = mumps_analysis_counts();
  return {now.analysed - analyses_at_start_.analysed, now.reused - analyses_at_start_.reused};
}

void IpoptStepSolver::derived(std::vector<NamedValue>& out) const {
  out.push_back({"ipopt.speed_scale_mm_s", speed_scale_});
  out.push_back({"ipopt.force_scale_N", force_scale_});
}

SolveOutcome IpoptStepSolver::solve(const StepView& v, StepProblem& problem, Vec& u) {
  // Rows: gamma_N(u) + g_from / dt >= 0 with v_a = T_a u_a + p_a.
  const DofMap& dofs = problem.dofs();
  const double inv_dt = v.dt > 0 ? 1.0 / v.dt : 0.0;
  std::vector<LinearRow> rows;
  std::vector<int> row_of;
  for (int j = 0; j < static_cast<int>(rows_->size()); ++j) {
    const PairKinematics& k = *(*rows_)[j].kin;
    LinearRow r;
    double constant = -k.offset.dot(k.n);
    for (int a = 0; a < k.k; ++a) {
      const NodeFrame& fr = dofs.frame(k.nodes[a]);
      constant += k.c[a] * k.n.dot(fr.p);
      for (int q = 0; q < fr.nfree; ++q) r.terms.emplace_back(fr.dof[q], k.c[a] * k.n.dot(fr.T.col(q)));
    }
    if (r.terms.empty()) continue;  // nothing free to move: the kernel's constraints decide
    r.lower = -(k.gap_from * inv_dt + constant);
    rows.push_back(std::move(r));
    row_of.push_back(j);
  }
  // A pass of the same solve (set_rows starts each) re-solves the same
  // program: Ipopt keeps its structure (its spaces and index maps) when
  // handed the same TNLP, and MUMPS its analysis (Ipopt 3.11 asks for one
  // at every solve regardless: mumps_analysis_reuse.hpp).
  const auto same = [](const LinearRow& a, const LinearRow& b) { return a.lower == b.lower && a.terms == b.terms; };
  if (IsNull(nlp_) || u.size() != nlp_unknowns_ || rows.size() != nlp_rows_.size() ||
      !std::equal(rows.begin(), rows.end(), nlp_rows_.begin(), same)) {
    nlp_ = nullptr;
    nlp_rows_ = std::move(rows);
    nlp_unknowns_ = u.size();
  }
  const std::vector<LinearRow>& rows_now = nlp_rows_;
  const bool cold = !(last_scale_ > 0);
  // Where the solution is near a known one, Ipopt starts from its
  // multipliers too, near the central path (warm_mu_init, warm_bound_push)
  // instead of re-entering it from mu_init: a friction pass re-solves the
  // same rows after a change of the objective alone (the last solve's
  // multipliers); a step's first solve starts from the rows' forces in the
  // last settled solve (BoundRow::start_force). A pass's start meets a
  // loose tol already, and Ipopt would stop there without following the
  // new bounds (a plain start's last Newton steps overshoot tol by orders):
  // warm starts are solved to warm_tol, but for the passes far from the
  // friction bounds' fixed point and a step's first pass, whose bounds are
  // a prediction (`loose`, the enforcement's call): their solutions only
  // give the next bounds; a loose solution is never the
  // one taken (IpoptEnforcement::settle). A warm attempt whose solution is
  // not taken (warm_max_iter) is solved again from the plain start.
  std::vector<double> start_lambda;
  if (warm_start_ && !cold) {
    if (warm_next_ && last_lambda_.size() == rows_now.size()) {
      start_lambda = last_lambda_;
    } else if (!warm_next_) {
      start_lambda.resize(rows_now.size());
      for (std::size_t j = 0; j < rows_now.size(); ++j) start_lambda[j] = -(*rows_)[row_of[j]].start_force;
    }
  }
  const bool loose = !start_lambda.empty() && loose_next_;
  last_loose_ = loose;
  warm_next_ = loose_next_ = false;
  used_ = static_cast<int>(rows_now.size());
  SolveOutcome result;
  NlpOutcome out;
  bool ok = false;
  if (!start_lambda.empty()) {
    use_warm_start(true, loose ? loose_tol_ : warm_tol_);
    out = optimize(problem, u, last_scale_, &start_lambda);
    use_warm_start(false, tol_);
    ok = conclude(v, problem, row_of, out, result);
    if (!ok) ++warm_failures_, last_loose_ = false;
  }
  if (!ok) {
    // The run's first solve starts cold, far from its solution: with
    // Ipopt's own initial barrier parameter (0.1), not the small one meant
    // for a start from the last velocities (mu_init; docs/notes.md, "What
    // moved").
    if (cold) {
      Vec R;
      problem.residual(u, R, last_scale_);
      app_->Options()->SetNumericValue("mu_init", kColdMuInit);
    }
    out = optimize(problem, u, last_scale_);
    if (cold) app_->Options()->SetNumericValue("mu_init", mu_init_);
    ok = conclude(v, problem, row_of, out, result);
  }
  if (!ok) return result;
  result.reason.clear();
  u = out.u;
  last_lambda_ = out.lambda;
  result.converged = true;
  return result;
}

bool IpoptStepSolver::conclude(const StepView& v, StepProblem& problem, const std::vector<int>& row_of,
                               NlpOutcome& out, SolveOutcome& result) {
  // Ipopt's absolute complementarity tolerance (N mm/s) comes from the
  // element forces of the last solve (at the run's first solve: of the
  // point Ipopt starts from). When the forces at the solution are smaller
  // (a first point contact) and the checked complementarity misses
  // kAcceptKkt, it solves once more from its solution with the tolerance
  // of the solution's forces.
  const auto finite = [&](const NlpOutcome& o) { return o.u.size() == nlp_unknowns_ && o.u.allFinite(); };
  result.iterations += out.iterations;
  if (finite(out)) {
    last_scale_ = measure(v, problem, nlp_rows_, row_of, out);
    if (out.status == Ipopt::SUCCESS && kkt_.complementarity > kAcceptKkt) {
      const Vec from = out.u;
      out = optimize(problem, from, last_scale_);
      result.iterations += out.iterations;
      if (finite(out)) last_scale_ = measure(v, problem, nlp_rows_, row_of, out);
    }
  }
  if (!finite(out)) {
    result.reason = "Ipopt: " + ipopt_status_text(out.status) + " (no finite solution)";
    return false;
  }
  result.residual = kkt_.stationarity;
  // Ipopt's stalls, at its "acceptable" point or at a tiny step (its
  // correction at round-off, as Newton's round-off floor in
  // solver/newton.cpp), are taken when the contact conditions hold to
  // kAcceptKkt and stationarity is within the floor Newton accepts, 100
  // tol_force (a virtual rigid body's terms leave 1e-6). Where the
  // residual's own round-off (kkt_.round_off, relative to the same force
  // scale) is larger, as in a step in which nothing is loaded yet (mortar
  // rows at a first touch, whose weighted gaps close over a step or two:
  // every element force is round-off and the scale is the force floor),
  // those relative measures cannot fall below it: forces and stationarity
  // within kRoundOffMultiple of it are round-off too.
  const double floor = kRoundOffMultiple * kkt_.round_off;
  const double kkt_limit = std::max(kAcceptKkt, floor);
  const bool contact_ok =
      kkt_.primal <= kAcceptPrimal && kkt_.dual <= kkt_limit && kkt_.complementarity <= kkt_limit;
  const bool stalled = out.status == Ipopt::STOP_AT_ACCEPTABLE_POINT || out.status == Ipopt::STOP_AT_TINY_STEP;
  const bool acceptable = contact_ok && stalled && kkt_.stationarity <= std::max(100 * round_off_force_, floor);
  if (out.status != Ipopt::SUCCESS && !acceptable) {
    char buf[200];
    std::snprintf(buf, sizeof buf, " (%d iterations; Kuhn-Tucker residuals: primal %.1e, dual %.1e, complementarity "
                  "%.1e, stationarity %.1e; its round-off %.1e)", out.iterations, kkt_.primal, kkt_.dual,
                  kkt_.complementarity, kkt_.stationarity, kkt_.round_off);
    result.reason = "Ipopt: " + ipopt_status_text(out.status) + buf;
    return false;
  }
  return true;
}

void IpoptStepSolver::use_warm_start(bool on, double tol) {
  auto& o = *app_->Options();
  o.SetStringValue("warm_start_init_point", on ? "yes" : "no");
  o.SetNumericValue("mu_init", on ? warm_mu_init_ : mu_init_);
  o.SetIntegerValue("max_iter", on ? warm_max_iter_ : max_iter_);
  o.SetNumericValue("tol", tol);
}

NlpOutcome IpoptStepSolver::optimize(StepProblem& problem, const Vec& from, double force,
                                     const std::vector<double>* lambda) {
  if (force > 0) app_->Options()->SetNumericValue("compl_inf_tol", kComplTolFactor * kAcceptKkt * force * speed_scale_);
  NlpOutcome out;
  struct Reuse {  // this solver's setting for its solves, the thread's restored after
    bool was;
    explicit Reuse(bool on) : was(set_mumps_analysis_reuse(on)) {}
    ~Reuse() { set_mumps_analysis_reuse(was); }
  } reuse(reuse_analysis_);
  if (IsValid(nlp_)) {
    // The same program again: Ipopt's warm_start_same_structure keeps its
    // spaces and the linear system's structure.
    nlp_->restart(from, lambda, out);
    app_->Options()->SetStringValue("warm_start_same_structure", "yes");
    app_->ReOptimizeTNLP(GetRawPtr(nlp_));
    app_->Options()->SetStringValue("warm_start_same_structure", "no");
  } else {
    nlp_ = new StepNlp(problem, nlp_rows_, from, force_scale_, speed_scale_, secant_after_cut_, out, lambda);
    app_->OptimizeTNLP(GetRawPtr(nlp_));
  }
  return out;
}

double IpoptStepSolver::measure(const StepView& v, const StepProblem& problem, const std::vector<LinearRow>& rows,
                                const std::vector<int>& row_of, const NlpOutcome& out) {
  // The Kuhn-Tucker conditions (paper eq. 6), checked here.
  // R(u) at the solution: Ipopt's last gradient where it was taken there
  // (the same bits as evaluating it again).
  Vec R = out.grad;
  double scale = out.grad_scale;
  if (R.size() != out.u.size()) problem.residual(out.u, R, scale);
  if (!(scale > 0)) scale = 1;
  Vec stat = R;
  for (auto& r : *rows_) r.force = 0, r.end_gap = r.kin->gap_from;
  kkt_ = Kkt{};
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const double lambda = out.lambda[j];
    double value = 0;
    for (const auto& [dof, a] : rows[j].terms) {
      value += a * out.u[dof];
      stat[dof] += a * lambda;
    }
    BoundRow& r = (*rows_)[row_of[j]];
    const double slack = value - rows[j].lower;  // mm/s
    r.force = -lambda;
    r.end_gap = v.dt * slack;
    kkt_.primal = std::max(kkt_.primal, std::max(0.0, -r.end_gap) / r.h);
    kkt_.dual = std::max(kkt_.dual, std::max(0.0, -r.force) / scale);
    kkt_.complementarity = std::max(kkt_.complementarity, std::abs(r.force * slack) / (scale * speed_scale_));
  }
  kkt_.stationarity = stat.norm() / scale;
  // The residual's own round-off: R at u with every component moved by one
  // unit in the last place (signs from a fixed hash), over the same scale.
  // A stationarity within a small multiple of this is the floor of
  // evaluating R in double precision, not a solver shortfall. Taken at a
  // step's first solve and at every solve Ipopt did not end with success
  // (where the acceptance needs it); the friction passes in between move u
  // too little to change it.
  if (!have_round_off_ || out.status != Ipopt::SUCCESS) {
    Vec u1 = out.u, R1;
    for (Index i = 0; i < u1.size(); ++i) {
      const double ulp = std::nextafter(std::abs(u1[i]), INFINITY) - std::abs(u1[i]);
      u1[i] += ((i * 2654435761u) >> 7) % 2 ? ulp : -ulp;
    }
    double s1 = 0;
    problem.residual(u1, R1, s1);
    round_off_ = (R1 - R).norm() / scale;
    have_round_off_ = true;
  }
  kkt_.round_off = round_off_;
  return scale;
}

}  // namespace rpfem
