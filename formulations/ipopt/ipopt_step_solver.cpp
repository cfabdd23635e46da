#include "ipopt/ipopt_step_solver.hpp"

#include <algorithm>
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
// Ipopt's default initial barrier parameter, for the run's cold first solve.
constexpr double kColdMuInit = 0.1;
// Gap and slip rates whose weights' Gram determinant is below this
// fraction of |a_N|^2 |a_T|^2 move along one direction: the row is
// frictionless (ipopt_step_solver.hpp).
constexpr double kParallel = 1e-12;

}  // namespace

IpoptStepSolver::IpoptStepSolver(const Scene& scene, CaseSection& settings, double force_scale)
    : force_scale_(std::max(force_scale, 1e-12)), polish_lu_(LinearSolverChoice::Lu, CholeskyMode::Supernodal, scene.solver.lu) {
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
  polish_ = settings.flag("polish", true);
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

void IpoptStepSolver::build_rows(const StepView& v, const StepProblem& problem, const Vec& u,
                                 std::vector<LinearRow>& rows, std::vector<double>& cost, Vec& x) {
  // Rows: gamma_N(u) + g_from / dt >= 0 with v_a = T_a u_a + p_a; exact
  // friction's s_j - gamma_T,j(u) >= 0 and s_j + gamma_T,j(u) >= 0
  // (ipopt_step_solver.hpp), gamma_T = a_T . u + t_0 alike along t.
  const DofMap& dofs = problem.dofs();
  const double inv_dt = v.dt > 0 ? 1.0 / v.dt : 0.0;
  const Index n = u.size();
  rows.clear();
  cost.clear();
  row_of_.clear();
  friction_of_.clear();
  struct Slip {
    std::vector<std::pair<Index, double>> at;
    double t0 = 0;
  };
  std::vector<Slip> slips;
  for (int j = 0; j < static_cast<int>(rows_->size()); ++j) {
    const BoundRow& b = (*rows_)[j];
    const PairKinematics& k = *b.kin;
    const Vec2 t(-k.n(1), k.n(0));
    LinearRow r;
    Slip slip;
    double constant = -k.offset.dot(k.n);
    slip.t0 = -k.offset.dot(t);
    for (int a = 0; a < k.k; ++a) {
      const NodeFrame& fr = dofs.frame(k.nodes[a]);
      constant += k.c[a] * k.n.dot(fr.p);
      slip.t0 += k.c[a] * t.dot(fr.p);
      for (int q = 0; q < fr.nfree; ++q) {
        r.terms.emplace_back(fr.dof[q], k.c[a] * k.n.dot(fr.T.col(q)));
        slip.at.emplace_back(fr.dof[q], k.c[a] * t.dot(fr.T.col(q)));
      }
    }
    if (r.terms.empty()) continue;  // nothing free to move: the kernel's constraints decide
    r.lower = -(k.gap_from * inv_dt + constant);
    rows.push_back(std::move(r));
    row_of_.push_back(j);
    if (!(b.exact_bound > 0)) continue;
    double nn = 0, tt = 0, nt = 0;
    for (std::size_t q = 0; q < slip.at.size(); ++q) {
      const double an = rows.back().terms[q].second, at = slip.at[q].second;
      nn += an * an, tt += at * at, nt += an * at;
    }
    if (nn * tt - nt * nt <= kParallel * nn * tt || tt <= kParallel * nn) continue;  // one direction: frictionless
    friction_of_.push_back(j);
    cost.push_back(b.exact_bound);
    slips.push_back(std::move(slip));
  }
  x.resize(n + static_cast<Index>(slips.size()));
  x.head(n) = u;
  for (std::size_t q = 0; q < slips.size(); ++q) {
    const Index s = n + static_cast<Index>(q);
    double gamma = slips[q].t0;
    LinearRow plus, minus;  // s - gamma_T >= 0, s + gamma_T >= 0
    for (const auto& [dof, a] : slips[q].at) {
      gamma += a * u[dof];
      plus.terms.emplace_back(dof, -a);
      minus.terms.emplace_back(dof, a);
    }
    plus.terms.emplace_back(s, 1.0);
    minus.terms.emplace_back(s, 1.0);
    plus.lower = slips[q].t0;
    minus.lower = -slips[q].t0;
    rows.push_back(std::move(plus));
    rows.push_back(std::move(minus));
    x[s] = std::abs(gamma);
  }
}

std::vector<double> IpoptStepSolver::row_multipliers(bool last_solve) const {
  // Ipopt's sign: lambda = -N. An exact friction row's p, q from its force
  // T = q - p and p + q = g (ipopt_step_solver.hpp), within [0, g].
  std::vector<double> lambda;
  lambda.reserve(row_of_.size() + 2 * friction_of_.size());
  for (int j : row_of_) lambda.push_back(-(last_solve ? (*rows_)[j].force : (*rows_)[j].start_force));
  for (int j : friction_of_) {
    const BoundRow& b = (*rows_)[j];
    const double g = b.exact_bound, T = last_solve ? b.friction : b.start_friction;
    const double p = std::clamp(0.5 * (g - T), 0.0, g);
    lambda.push_back(-p);
    lambda.push_back(-(g - p));
  }
  return lambda;
}

SolveOutcome IpoptStepSolver::solve(const StepView& v, StepProblem& problem, Vec& u) {
  std::vector<LinearRow> rows;
  std::vector<double> cost;
  const std::vector<int> friction_before = friction_of_;
  Vec x;
  build_rows(v, problem, u, rows, cost, x);
  // A pass of the same solve (set_rows starts each) re-solves the same
  // program: Ipopt keeps its structure (its spaces and index maps) when
  // handed the same TNLP, and MUMPS its analysis (Ipopt 3.11 asks for one
  // at every solve regardless: mumps_analysis_reuse.hpp). The slacks'
  // costs (the exact friction bounds) are the objective's: they may change.
  const auto same = [](const LinearRow& a, const LinearRow& b) { return a.lower == b.lower && a.terms == b.terms; };
  const bool same_program = IsValid(nlp_) && u.size() == nlp_unknowns_ && rows.size() == nlp_rows_.size() &&
                            friction_of_ == friction_before &&
                            std::equal(rows.begin(), rows.end(), nlp_rows_.begin(), same);
  if (!same_program) {
    nlp_ = nullptr;
    nlp_rows_ = std::move(rows);
    nlp_unknowns_ = u.size();
  }
  nlp_cost_ = cost;  // in place: the program reads it at every evaluation
  const std::vector<LinearRow>& rows_now = nlp_rows_;
  const bool cold = !(last_scale_ > 0);
  // Where the solution is near a known one, Ipopt starts from its
  // multipliers too, near the central path (warm_mu_init, warm_bound_push)
  // instead of re-entering it from mu_init: a friction pass re-solves the
  // same rows after a change of the objective alone (the last solve's
  // multipliers; the last solve's forces where exact friction rows came or
  // went with the bounds); a step's first solve starts from the rows'
  // forces in the last settled solve (BoundRow::start_force,
  // start_friction). A pass's start meets a
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
    if (warm_next_ && same_program && last_lambda_.size() == rows_now.size()) start_lambda = last_lambda_;
    else if (!warm_next_ || !friction_of_.empty() || !friction_before.empty()) start_lambda = row_multipliers(warm_next_);
  }
  const bool loose = !start_lambda.empty() && loose_next_;
  last_loose_ = loose;
  warm_next_ = loose_next_ = false;
  used_ = static_cast<int>(row_of_.size());
  SolveOutcome result;
  NlpOutcome out;
  bool ok = false;
  if (!start_lambda.empty()) {
    use_warm_start(true, loose ? loose_tol_ : warm_tol_);
    out = optimize(problem, x, last_scale_, &start_lambda);
    use_warm_start(false, tol_);
    ok = conclude(v, problem, out, result);
    if (!ok) ++warm_failures_, last_loose_ = false;
  }
  if (!ok) {
    // The run's first solve starts cold, far from its solution: with
    // Ipopt's own initial barrier parameter (0.1), not the small one meant
    // for a start from the last velocities (mu_init; docs/decisions.md, "ipopt").
    if (cold) {
      Vec R;
      problem.residual(u, R, last_scale_);
      app_->Options()->SetNumericValue("mu_init", kColdMuInit);
    }
    out = optimize(problem, x, last_scale_);
    if (cold) app_->Options()->SetNumericValue("mu_init", mu_init_);
    ok = conclude(v, problem, out, result);
  }
  if (!ok) return result;
  result.reason.clear();
  // The next pass starts from Ipopt's own multipliers (its central path),
  // not the polished ones (zero on the inactive rows).
  last_lambda_ = out.lambda;
  polished_ = false;
  if (polish_ && !nlp_cost_.empty() && polish(problem, out)) {
    polished_ = true;
    last_scale_ = measure(v, problem, out);
  }
  u = out.u;
  result.converged = true;
  return result;
}

bool IpoptStepSolver::conclude(const StepView& v, StepProblem& problem, NlpOutcome& out, SolveOutcome& result) {
  // Ipopt's absolute complementarity tolerance (N mm/s) comes from the
  // element forces of the last solve (at the run's first solve: of the
  // point Ipopt starts from). When the forces at the solution are smaller
  // (a first point contact) and the checked complementarity misses
  // kAcceptKkt, it solves once more from its solution with the tolerance
  // of the solution's forces.
  const auto finite = [&](const NlpOutcome& o) {
    return o.u.size() == nlp_unknowns_ && o.u.allFinite() && o.slack.size() == static_cast<Index>(nlp_cost_.size()) &&
           o.slack.allFinite();
  };
  result.iterations += out.iterations;
  if (finite(out)) {
    last_scale_ = measure(v, problem, out);
    if (out.status == Ipopt::SUCCESS && kkt_.complementarity > kAcceptKkt) {
      Vec from(out.u.size() + out.slack.size());
      from.head(out.u.size()) = out.u;
      from.tail(out.slack.size()) = out.slack;
      out = optimize(problem, from, last_scale_);
      result.iterations += out.iterations;
      if (finite(out)) last_scale_ = measure(v, problem, out);
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
    nlp_ = new StepNlp(problem, nlp_rows_, nlp_cost_, from, force_scale_, speed_scale_, secant_after_cut_, out, lambda);
    app_->OptimizeTNLP(GetRawPtr(nlp_));
  }
  return out;
}

double IpoptStepSolver::measure(const StepView& v, const StepProblem& problem, const NlpOutcome& out) {
  // The Kuhn-Tucker conditions (paper eq. 6; for exact friction those of
  // the slacks' program, ipopt_step_solver.hpp), checked here.
  // R(u) at the solution: Ipopt's last gradient where it was taken there
  // (the same bits as evaluating it again).
  Vec R = out.grad;
  double scale = out.grad_scale;
  if (R.size() != out.u.size()) problem.residual(out.u, R, scale);
  if (!(scale > 0)) scale = 1;
  const Index n = out.u.size();
  const std::size_t normal = row_of_.size();
  Vec x(n + out.slack.size()), stat(x.size());
  x.head(n) = out.u;
  x.tail(out.slack.size()) = out.slack;
  stat.head(n) = R;
  for (std::size_t q = 0; q < nlp_cost_.size(); ++q) stat[n + static_cast<Index>(q)] = nlp_cost_[q];  // g_j
  for (auto& r : *rows_) r.force = 0, r.end_gap = r.kin->gap_from, r.friction = 0, r.friction_rows = false;
  kkt_ = Kkt{};
  for (std::size_t j = 0; j < nlp_rows_.size(); ++j) {
    const double lambda = out.lambda[j];
    double value = 0;
    for (const auto& [dof, a] : nlp_rows_[j].terms) {
      value += a * x[dof];
      stat[dof] += a * lambda;
    }
    const double slack = value - nlp_rows_[j].lower;  // mm/s
    BoundRow& r = (*rows_)[j < normal ? row_of_[j] : friction_of_[(j - normal) / 2]];
    if (j < normal) {
      r.force = -lambda;
      r.end_gap = v.dt * slack;
      kkt_.primal = std::max(kkt_.primal, std::max(0.0, -r.end_gap) / r.h);
    } else {
      // T = q - p = lambda_plus - lambda_minus (rows s - gamma_T, s + gamma_T).
      r.friction += (j - normal) % 2 ? -lambda : lambda;
      r.friction_rows = true;
      kkt_.primal = std::max(kkt_.primal, v.dt * std::max(0.0, -slack) / r.h);
    }
    kkt_.dual = std::max(kkt_.dual, std::max(0.0, lambda) / scale);
    kkt_.complementarity = std::max(kkt_.complementarity, std::abs(lambda * slack) / (scale * speed_scale_));
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
