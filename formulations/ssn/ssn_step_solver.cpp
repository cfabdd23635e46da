#include "ssn/ssn_step_solver.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "model/step_problem.hpp"

namespace rpfem {

namespace {

// Gap and slip rates whose weights' Gram determinant is below this
// fraction of |a_N|^2 |a_T|^2 move along one direction.
constexpr double kParallel = 1e-12;
// A converged row in contact is within kRowGap of the element size of its
// master at the step's end and a sticking row slips at most kRowSlip of
// the speed scale (the conditions the enforcement checks at 1e-9 and 1e-8).
constexpr double kRowGap = 1e-11, kRowSlip = 1e-10;
// A step whose residual on its own sets exceeds this many times the
// iterate's, and kGrowthFloor of the force scale, is cut.
constexpr double kGrowth = 10, kGrowthFloor = 1e-3;

// A row's set: 0 inactive, 1 and 2 slipping either way, 3 sticking.
char set_of(const RowNcp& n) { return n.active ? (n.stick ? 3 : n.sign > 0 ? 1 : 2) : 0; }
// A row whose set changed this many times in a solve is held on its
// branch until the Newton iteration converges on the sets held, counted
// in iterations where at most kFewChanges rows (or a tenth of them)
// changed.
constexpr int kHoldAfter = 3;
constexpr std::size_t kFewChanges = 3;
// A slipping row may slip along its own friction force by this fraction of
// the speed scale (the tolerance the enforcement checks a sticking row's
// slip rate at: at its bound and within it, such a row meets the sticking
// conditions there).
constexpr double kAlongForce = 1e-8;
// A held row whose own set differs at the held solution is held on that
// set at most this many times, then released.
constexpr int kMaxRehold = 3;
// c_tangential above this: a failure names it (solve()).
constexpr double kLargeTangential = 1;
// A cold solve's rounds at most (solve(): 4 and 6 on the 72 x 48 ring at
// m = 0.1).
constexpr int kMaxColdRounds = 10;
// A grazing row's friction force may exceed its bound by this fraction
// (round-off of the solve).
constexpr double kGrazingTolerance = 1e-9;

}  // namespace

SsnStepSolver::SsnStepSolver(SsnSettings s)
    : s_(s), lu_(LinearSolverChoice::Lu, CholeskyMode::Supernodal, s.lu),
      cholesky_(LinearSolverChoice::Cholmod),
      augmented_cholesky_(LinearSolverChoice::Cholmod) {}

void SsnStepSolver::reduce_rows(const StepView& v, const StepProblem& problem) {
  // r = gamma_N + g_from / dt and gamma_T with v_a = T_a u_a + p_a.
  const DofMap& dofs = problem.dofs();
  const double inv_dt = v.dt > 0 ? 1.0 / v.dt : 0.0;
  red_.clear();
  for (std::size_t j = 0; j < rows_->size(); ++j) {
    const ContactRow& row = (*rows_)[j];
    if (row.free) continue;
    const PairKinematics& k = row.kin;
    const Vec2 t(-k.n(1), k.n(0));
    Reduced r;
    r.row = j;
    r.cn = (*c_)[2 * j], r.ct = (*c_)[2 * j + 1];
    r.r0 = -k.offset.dot(k.n) + k.gap_from * inv_dt;
    r.t0 = -k.offset.dot(t);
    for (int a = 0; a < k.k; ++a) {
      const NodeFrame& fr = dofs.frame(k.nodes[a]);
      r.r0 += k.c[a] * k.n.dot(fr.p);
      r.t0 += k.c[a] * t.dot(fr.p);
      for (int q = 0; q < fr.nfree; ++q) {
        r.an.emplace_back(fr.dof[q], k.c[a] * k.n.dot(fr.T.col(q)));
        r.at.emplace_back(fr.dof[q], k.c[a] * t.dot(fr.T.col(q)));
      }
    }
    if (r.an.empty()) continue;  // nothing free to move: the kernel's constraints decide
    double nn = 0, tt = 0, nt = 0;
    for (std::size_t q = 0; q < r.an.size(); ++q)
      nn += r.an[q].second * r.an[q].second, tt += r.at[q].second * r.at[q].second, nt += r.an[q].second * r.at[q].second;
    // (Or the slip rate is fixed by the kernel's constraints: both sides
    // on a symmetry plane.) Or the slave node itself moves along one
    // direction (the header: a mortar row of a node on a symmetry plane
    // or the axis).
    r.one_direction = nn * tt - nt * nt <= kParallel * nn * tt || tt <= kParallel * nn ||
                      dofs.frame(k.nodes[0]).nfree == 1;
    r.die_node = k.k == 1 ? k.nodes[0] : -1;  // against a die: the node alone
    red_.push_back(std::move(r));
  }
}

void SsnStepSolver::forces(StepProblem& problem, Iterate& it) {
  it.energy = problem.residual_energy(it.u, it.R, it.scale);
}

double SsnStepSolver::lagrangian(const Iterate& it, const std::vector<double>& ln, const std::vector<double>& lt) const {
  double L = it.energy;
  for (std::size_t j = 0; j < red_.size(); ++j) L -= ln[j] * it.r[j] + lt[j] * it.g[j];
  return L;
}

void SsnStepSolver::rows(const StepView& v, Iterate& it, const Iterate* branch, bool hold) {
  const Index n = it.u.size();
  const std::size_t m = red_.size();
  it.F.resize(n + 2 * static_cast<Index>(m));
  it.F.head(n) = it.R;
  std::vector<double>& r = it.r;
  std::vector<double>& g = it.g;
  r.resize(m), g.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const Reduced& rr = red_[j];
    r[j] = rr.r0, g[j] = rr.t0;
    for (const auto& [d, w] : rr.an) r[j] += w * it.u[d];
    for (const auto& [d, w] : rr.at) g[j] += w * it.u[d];
  }
  if (!branch) {
    // The active set first: the friction bounds depend on it (contact
    // areas); on a kept branch they are the branch's.
    // A row held grazing touches at zero force: its area counts whether
    // held or not (the check of the sets a held solution asks for, where
    // its force's round-off sign would otherwise halve its neighbours'
    // areas and bounds and send them slipping).
    std::fill(active_rows_.begin(), active_rows_.end(), 0);
    for (std::size_t j = 0; j < m; ++j)
      active_rows_[red_[j].row] = held_[j] && (hold || held_[j]->grazing) ? held_[j]->active
                                                                         : it.ln[j] - red_[j].cn * r[j] > 0;
    frictions_(v, active_rows_, friction_);
    // A node in contact with two dies (both rows active): neither row
    // sticks with a force (ncp.hpp, may_stick).
    std::map<Index, int> pressing;
    for (std::size_t j = 0; j < m; ++j)
      if (red_[j].die_node >= 0 && active_rows_[red_[j].row]) ++pressing[red_[j].die_node];
    shared_.assign(m, 0);
    for (std::size_t j = 0; j < m; ++j)
      shared_[j] = red_[j].die_node >= 0 && active_rows_[red_[j].row] && pressing[red_[j].die_node] > 1;
  }
  it.ncp.resize(m);
  it.sets.resize(m);
  for (std::size_t j = 0; j < m; ++j) {
    const Reduced& rr = red_[j];
    for (const auto& [d, w] : rr.an) it.F[d] -= it.ln[j] * w;
    for (const auto& [d, w] : rr.at) it.F[d] -= it.lt[j] * w;
    RowFriction f = rr.one_direction ? RowFriction{} : friction_[rr.row];
    f.may_stick = !shared_[j];
    const RowNcp* b = branch ? &branch->ncp[j] : hold && held_[j] ? &*held_[j] : nullptr;
    it.ncp[j] = row_ncp(it.ln[j], it.lt[j], r[j], g[j], rr.cn, rr.ct, f, b);
    it.F[n + 2 * j] = it.ncp[j].cn;
    it.F[n + 2 * j + 1] = it.ncp[j].ct;
    it.sets[j] = set_of(it.ncp[j]);
  }
  it.norm = it.F.norm();
}

void SsnStepSolver::start(const StepView& v, const StepProblem& problem) {
  reduce_rows(v, problem);
  const std::size_t m = red_.size();
  active_rows_.assign(rows_->size(), 0);
  friction_.assign(rows_->size(), {});
  held_.assign(m, std::nullopt);
  flips_.assign(m, 0);
  normal_flips_.assign(m, 0);
  reholds_.assign(m, 0);
  saddle_hashed_ = condensed_hashed_ = augmented_hashed_ = false;
}

SpMat SsnStepSolver::system(const StepView& v, StepProblem& problem, const Vec& x, Vec& F) {
  start(v, problem);
  const Index n = problem.dofs().num_free();
  Iterate it;
  it.u = x.head(n);
  for (std::size_t j = 0; j < red_.size(); ++j) it.ln.push_back(x[n + 2 * j]), it.lt.push_back(x[n + 2 * j + 1]);
  forces(problem, it);
  rows(v, it, nullptr);
  F = it.F;
  return jacobian(problem.tangent(it.u, true), it);
}

bool SsnStepSolver::rows_meet(const StepView& v, const Iterate& it) const {
  // |F| bounds the rows' functions in N, against the elements' force
  // scale: a row of small c could keep a visible gap or slip within it.
  for (std::size_t j = 0; j < red_.size(); ++j) {
    const RowNcp& q = it.ncp[j];
    if (q.active && std::abs(it.r[j]) * v.dt > kRowGap * (*rows_)[red_[j].row].h) return false;
    if (q.active && q.stick && std::abs(it.g[j]) > kRowSlip * s_.speed_scale) return false;
  }
  return true;
}

bool SsnStepSolver::grazing_holds(const Iterate& it, std::size_t j) const {
  // The friction force within the bound, and not along the slip.
  const RowNcp& q = it.ncp[j];
  const double tol = kGrazingTolerance * std::max(q.g, 1e-300);
  return std::abs(it.lt[j]) <= q.g + tol && it.lt[j] * it.g[j] <= tol * std::abs(it.g[j]);
}

SsnStepSolver::Start SsnStepSolver::first_iterate(const StepView& v, StepProblem& problem, const Vec& u) {
  const std::size_t m = red_.size();
  Start start;
  Iterate& x = start.x;
  bool &cold = start.cold, &warm = start.warm;
  x.u = u;
  x.ln.resize(m), x.lt.resize(m);
  for (std::size_t j = 0; j < m; ++j) x.ln[j] = (*state_)[red_[j].row].lambda_n, x.lt[j] = (*state_)[red_[j].row].lambda_t;
  warm = !hold_start_;
  forces(problem, x);
  // A row with no forces of its own yet (a run's first solve, the first
  // after a remesh) that touches at the start takes the force its nodes'
  // elements exert along its weights, R . a / |a|^2: the contact force
  // equilibrium asks of it if it alone held them. Started from zero, the
  // rows of a slug in its container after a remesh changed sets by the
  // dozen per iteration and the solve diverged.
  for (std::size_t j = 0; j < m; ++j) {
    const SsnRowState& st = (*state_)[red_[j].row];
    if (st.active || st.lambda_n != 0) {
      cold = false;
      continue;
    }
    const Reduced& rr = red_[j];
    double r = rr.r0, nn = 0, tt = 0, fn = 0, ft = 0;
    for (const auto& [d, w] : rr.an) r += w * x.u[d], nn += w * w, fn += w * x.R[d];
    for (const auto& [d, w] : rr.at) tt += w * w, ft += w * x.R[d];
    if (!(r <= 0) || !(nn > 0)) continue;
    x.ln[j] = std::max(0.0, fn / nn);
    warm = false;
    if (x.ln[j] > 0 && tt > 0) x.lt[j] = ft / tt;
  }
  rows(v, x, nullptr, true);
  // A row that slipped in its last solve starts at its present bound: the
  // bound grows with the contact area (k w) or the pressure (Coulomb), so
  // the last force, at the last bound, lies inside the present one and
  // read as sticking, which the first Newton step then takes back
  // (the ring at m = 1: 7 of 25 rows a solve).
  // A row that touches with no force of its own (a node landing while it
  // slides) starts slipping at its bound, against its slip: read from
  // zero force, c_T gamma_T < g held every slip slower than about six
  // times the die speed sticking, and the first Newton step stopped the
  // sliding node and moved most of the contact zone's sets (the ring at
  // m = 1 as its inner face folds onto the die: 14 of 54 rows).
  bool rescaled = false;
  for (std::size_t j = 0; j < m; ++j) {
    const SsnRowState& st = (*state_)[red_[j].row];
    if (!x.ncp[j].active || x.ncp[j].g <= 0) continue;
    if (st.active && !st.stick && !st.grazing && x.lt[j] != 0) {
      x.lt[j] = std::copysign(x.ncp[j].g, x.lt[j]);
      rescaled = true;
    } else if (!st.active && x.ln[j] == 0 && x.lt[j] == 0 && std::abs(x.g[j]) > kRowSlip * s_.speed_scale) {
      x.lt[j] = -std::copysign(x.ncp[j].g, x.g[j]);
      rescaled = true;
    }
  }
  if (rescaled) rows(v, x, nullptr, true);
  cold = cold || hold_start_;
  if (hold_start_) {
    for (std::size_t j = 0; j < m; ++j) held_[j] = x.ncp[j], held_[j]->grazing = false;
    hold_start_ = false;
  }
  return start;
}

SsnStepSolver::Search SsnStepSolver::line_search(const StepView& v, StepProblem& problem, const Iterate& x, const Vec& dx,
                                                 bool keep_full_step, bool probe) {
  const NewtonSettings& ns = s_.newton;
  const Index n = x.u.size();
  const std::size_t m = red_.size();
  // Backtracking on the Lagrangian of the iterate's sets (the header).
  std::vector<double> ln_plus = x.ln, lt_plus = x.lt;
  for (std::size_t j = 0; j < m; ++j) ln_plus[j] += dx[n + 2 * j], lt_plus[j] += dx[n + 2 * j + 1];
  const double L0 = lagrangian(x, ln_plus, lt_plus);
  Vec Fu = x.F.head(n);
  for (std::size_t j = 0; j < m; ++j) {
    for (const auto& [d, w] : red_[j].an) Fu[d] += (x.ln[j] - ln_plus[j]) * w;
    for (const auto& [d, w] : red_[j].at) Fu[d] += (x.lt[j] - lt_plus[j]) * w;
  }
  const double slope = Fu.dot(dx.head(n));
  Search out;
  Iterate& trial = out.trial;
  double& s = out.s;
  for (int cut = 0;; ++cut) {
    trial.u = x.u + s * dx.head(n);
    trial.ln = x.ln, trial.lt = x.lt;
    for (std::size_t j = 0; j < m; ++j) trial.ln[j] += s * dx[n + 2 * j], trial.lt[j] += s * dx[n + 2 * j + 1];
    const bool keep = keep_full_step && cut == 0;
    if (keep) problem.keep_tangent_terms(true);
    forces(problem, trial);
    if (keep) problem.keep_tangent_terms(false);
    rows(v, trial, &x);
    const double L = lagrangian(trial, ln_plus, lt_plus);
    bool ok = std::isfinite(L) && std::isfinite(trial.norm);
    if (ok && slope < 0) {
      // Within round-off of L(u) a drop of |F| is taken instead (as the
      // kernel's Newton does, solver/newton.hpp).
      ok = L <= L0 + ns.armijo * s * slope ||
           (L - L0 <= kRoundOffEnergy * std::abs(L0) && trial.norm <= (1 - ns.armijo * s) * x.norm);
    } else if (ok) {
      ok = trial.norm <= (1 - ns.armijo * s) * x.norm;
    }
    // The sets at the trial; nor may the residual on them grow beyond
    // kGrowth times: the Lagrangian of one iterate's sets falls along
    // steps that change many sets at once while |F| grows without bound
    // (the backward extrusion after a remesh: 1e8 times). Below
    // kGrowthFloor of the force scale it may: the step off a converged
    // iterate whose released rows took a new set starts at |F| ~ 1e-9
    // and passes 1e-5 on its way (cut to 2^-12 at 10 times, 2^-5 at
    // the next, and the solve crawled).
    if (ok || cut == ns.max_halvings) rows(v, trial, nullptr, true);
    if (ok) ok = trial.norm <= std::max(kGrowth * x.norm, kGrowthFloor * x.scale);
    if (ok) break;
    if (probe) {
      out.redo = true;
      break;
    }
    if (cut == ns.max_halvings) break;  // the shortest step is taken: the secant iteration follows
    s *= 0.5, ++stats_.halvings;
  }
  return out;
}

std::string SsnStepSolver::landing_lift_off(const StepView& v, const Iterate& x, const Iterate& trial) const {
  // A row landing at the step's end that, pressing and slipping at the
  // friction factor's bound, lifts off: its bound m k w does not vanish
  // with the pressure, so pressing its friction lifts it off, free it
  // penetrates, and it may have no solution there (ncp.hpp, grazing).
  // Where the inner face of the ring at m = 1 folds onto the die (72 x
  // 48), such a row pressing at its bound ended with -264 N, and its
  // turns moved 10 to 60 rows beside the sticking zone between stick and
  // slip at each iteration: the solve ran out of its 40 iterations. Past
  // the landing the row presses and has a solution: the stepper tries
  // the step there (StepView::at_landing). Open at the start: not active
  // in the state the solve started from (written only when it converges).
  for (std::size_t j = 0; j < red_.size() && v.at_landing; ++j) {
    const RowNcp &was = x.ncp[j], &is = trial.ncp[j];
    if ((*state_)[red_[j].row].active || !was.active || was.stick || was.grazing || is.active || red_[j].one_direction ||
        friction_[red_[j].row].kind != RowFriction::Kind::Tresca)
      continue;
    return "ssn: the row of node " + std::to_string((*rows_)[red_[j].row].kin.nodes[0]) +
           " landing at the step's end lifts off when it presses at its friction bound";
  }
  return "";
}

void SsnStepSolver::hold_cycling(const Iterate& x, const Iterate& trial, int changes) {
  const std::size_t m = red_.size();
  // Cycling is a few rows changing by turns; many rows changing at once
  // is the sets being found (a cold start).
  const bool few = static_cast<std::size_t>(changes) <= std::max(kFewChanges, m / 10);
  for (std::size_t j = 0; j < m && few; ++j) {
    if (trial.sets[j] == x.sets[j]) continue;
    if (trial.ncp[j].active != x.ncp[j].active) ++normal_flips_[j];
    if (++flips_[j] >= kHoldAfter && !held_[j]) {
      // A row that lands and lifts off by turns under the friction
      // factor's jump is held grazing (ncp.hpp), any other on its branch.
      held_[j] = trial.ncp[j];
      held_[j]->grazing = normal_flips_[j] >= kHoldAfter - 1 && friction_[red_[j].row].kind == RowFriction::Kind::Tresca;
      if (held_[j]->grazing) held_[j]->active = true;
      ++stats_.holds;
    }
  }
}

int SsnStepSolver::release(const StepView& v, const Iterate& x, Iterate& free, bool round_off, bool& stuck) {
  const NewtonSettings& ns = s_.newton;
  const std::size_t m = red_.size();
  rows(v, free, nullptr, false);
  const bool free_meets = free.norm <= (round_off ? kRoundOffFactor : 1.0) * ns.tol_force * free.scale &&
                          rows_meet(v, free);
  int released = 0;
  stuck = false;
  for (std::size_t j = 0; j < m; ++j) {
    if (!held_[j]) continue;
    const bool holds = held_[j]->grazing ? grazing_holds(x, j) : free_meets || free.sets[j] == set_of(*held_[j]);
    if (holds) continue;
    // A grazing row that came back to the jump after kMaxRehold outer
    // steps has no solution on any branch (pressing at the bound it
    // lifts off, free it penetrates, grazing it asks for more friction
    // than the bound or friction along its slip: a rim row of the
    // friction factor law, whose bound m k w does not vanish with the
    // pressure). It stays grazing, the least departure from the law at
    // one row; the enforcement reports its friction against the bound
    // (kkt_friction) and the run warns.
    if (held_[j]->grazing && reholds_[j] >= kMaxRehold) continue;
    ++released;
    if (held_[j]->grazing && std::abs(x.lt[j]) > x.ncp[j].g) {
      // Grazing asks for more friction than the bound: the row presses
      // and slips at the bound, the force opposing its slip (the law),
      // or, at no slip, along the force equilibrium asked for.
      held_[j]->grazing = held_[j]->stick = false;
      const double slip = x.g[j];
      const bool slips = std::abs(slip) > kRowSlip * s_.speed_scale;
      held_[j]->sign = slips ? (slip > 0 ? -1.0 : 1.0) : (x.lt[j] > 0 ? 1.0 : -1.0);
      continue;
    }
    // Held again on its own branch at this solution, while that
    // converges: a row at the stick-slip boundary goes to the side the
    // held solution asks for (an outer step of the primal-dual active
    // set method for the few rows that cycle); released for good
    // after kMaxRehold of them.
    if (++reholds_[j] <= kMaxRehold) held_[j] = free.ncp[j];
    else held_[j].reset(), flips_[j] = normal_flips_[j] = 0;
  }
  // A slipping row whose slip runs along its own friction force meets
  // neither set's conditions, yet its own set reads as slipping: its
  // force lies at the bound to within the force tolerance (tol_force
  // F_scale), and that is more than c_T gamma_T for a slip rate below
  // about 1e-4 of the die speed. Held sticking, the iteration goes on;
  // after kMaxRehold such holds it is left, kkt_friction reports it and
  // the run warns. The remeshed ring's 72 x 48 mesh under Coulomb (mu =
  // 0.2) ended two steps with such rows (slip rates 3e-6 to 4e-3 of the
  // die speed, each held on its slipping branch after cycling), and at
  // 48 x 32 one (kkt_friction 2 at 5.29 mm); with the hold, none.
  for (std::size_t j = 0; j < m; ++j) {
    const RowNcp& q = x.ncp[j];
    if (!q.active || q.stick || q.grazing || x.g[j] * q.sign <= kAlongForce * s_.speed_scale) continue;
    if (reholds_[j] >= kMaxRehold) continue;
    ++reholds_[j], ++released, stuck = true;
    held_[j] = q;
    held_[j]->stick = true, held_[j]->sign = 0;
  }
  return released;
}

void SsnStepSolver::store(const Iterate& x, Vec& u) {
  const std::size_t m = red_.size();
  u = x.u;
  for (std::size_t j = 0; j < m; ++j) {
    SsnRowState& st = (*state_)[red_[j].row];
    const RowNcp& q = x.ncp[j];
    st.lambda_n = x.ln[j], st.lambda_t = x.lt[j];
    // The forces on their branch's values, where those are explicit (the
    // iteration leaves them within tol_force of the force scale, which on
    // a lightly loaded row is a visible share of its bound): no force off
    // contact, a slipping row's force at its bound.
    if (!q.active) st.lambda_n = st.lambda_t = 0;
    else if (!q.stick && !q.grazing) st.lambda_t = q.g * q.sign;
    st.active = q.active, st.stick = q.stick, st.bound = q.g, st.grazing = q.grazing;
    stats_.grazing += q.grazing;
    st.end_gap_rate = x.r[j], st.slip_rate = x.g[j];
  }
}

SolveOutcome SsnStepSolver::solve(const StepView& v, StepProblem& problem, Vec& u) {
  SolveOutcome out;
  stats_ = {};
  start(v, problem);
  const std::size_t m = red_.size();
  stats_.rows = static_cast<int>(m);
  // Rows left out of the solve carry nothing.
  std::vector<char> in_solve(rows_->size(), 0);
  for (const Reduced& r : red_) in_solve[r.row] = 1;
  for (std::size_t j = 0; j < rows_->size(); ++j)
    if (!in_solve[j]) (*state_)[j] = {};
  const NewtonSettings& ns = s_.newton;
  bool secant = ns.direct_iterations > 0;
  Start start = first_iterate(v, problem, u);
  Iterate x = std::move(start.x);
  const bool cold = start.cold, warm = start.warm;
  double last_full = -1;  // |du| of the last full consistent step (-1: none)
  // A warm start's first iteration probes the consistent tangent (the
  // header); redone with the secant one, and counted, where that fails.
  const bool probing = secant && warm;
  if (probing) secant = false;
  int redone = 0;
  // A cold solve: a run's first (no row has forces from an earlier solve)
  // or the first after a remesh (hold_starting_sets()). Its sets are
  // found from scratch, in rounds (the iteration converging on the sets
  // held, then releasing the rows whose own set differs), and each round
  // has the scene's solver.max_iterations, as each contact pass of the
  // other enforcements' solves has (model/stepper.cpp). The 72 x 48 ring
  // at m = 0.1 found its first solve's sets in 4 rounds and 58 iterations
  // (27 to converge on the first sets held), and stopped there on one
  // budget of 40; a warm solve keeps the one budget.
  int round_start = 0;  // the iterations before this round (cold solves)
  for (int iter = 1;; ++iter) {
    if (iter + redone - round_start > ns.max_iterations) {
      out.reason = "ssn: no convergence in " + std::to_string(ns.max_iterations) + " iterations" +
                   (stats_.rounds > 0 ? " of round " + std::to_string(stats_.rounds + 1) : "") + " (|F| / F_scale = " +
                   std::to_string(x.norm / x.scale) + ")";
      break;
    }
    const SpMat& K = problem.tangent(x.u, !secant);
    Vec dx;
    if (!newton_step(K, x, dx)) {
      out.reason = "ssn: singular or non-finite Newton system";
      break;
    }
    const Index n = x.u.size();
    // The full-step trial is usually the next iterate, whose consistent
    // tangent then comes from the trial's own element pass (as the
    // kernel's Newton does, solver/newton.hpp), unless this is the last
    // iteration or the step's correction already predicts convergence
    // (two full consistent steps contracting below the tolerance).
    const double dun = dx.head(n).norm();
    const bool predicted = !secant && last_full > 0 && dun < 0.5 * last_full &&
                           dun / last_full * dun <= ns.tol_velocity * x.u.norm();
    const bool keep_full_step = iter + redone - round_start < ns.max_iterations && !predicted;
    const bool probe = probing && iter == 1 && !secant;
    Search search = line_search(v, problem, x, dx, keep_full_step, probe);
    Iterate& trial = search.trial;
    const double s = search.s;
    bool redo = search.redo;
    for (std::size_t j = 0; j < m && probe && !redo; ++j) redo = trial.ncp[j].active != x.ncp[j].active;
    if (redo) {
      secant = true, ++redone, --iter;
      continue;
    }
    if (!std::isfinite(trial.norm)) {
      out.reason = "ssn: non-finite residual";
      break;
    }
    const double du = s * dx.head(n).norm();
    int changes = 0;
    for (std::size_t j = 0; j < m; ++j) changes += trial.sets[j] != x.sets[j];
    out.reason = landing_lift_off(v, x, trial);
    if (!out.reason.empty()) break;
    hold_cycling(x, trial, changes);
    stats_.set_changes += changes;
    // The velocity error: the last correction, times the contraction of
    // two successive full consistent steps where it is below 1/2.
    double error = du;
    const bool full = s == 1 && !secant;
    if (full && last_full > 0 && du < 0.5 * last_full) error = du * du / last_full;
    last_full = full ? du : -1;
    secant = s < 1 && ns.secant_after_cut;
    x = std::move(trial);
    stats_.iterations = iter + redone;
    const double unorm = std::max(x.u.norm(), 1e-300);
    // At round-off: the correction below kRoundOffCorrection of |u| with
    // |F| within kRoundOffFactor of the tolerance, as the kernel's Newton
    // accepts (solver/newton.hpp; a virtual rigid body's large forces set
    // the floor of Test II's F near 1e-6).
    const bool round_off = du <= kRoundOffCorrection * unorm && x.norm <= kRoundOffFactor * ns.tol_force * x.scale;
    // F on the iterate's own sets is the conditions' residual: within the
    // tolerance the iterate meets them, whether or not a row changed its
    // set in the last step (a row at the kink between two sets, at zero
    // slip with its force at the bound, meets both and may swap between
    // them at round-off).
    if (((x.norm <= ns.tol_force * x.scale && error <= ns.tol_velocity * unorm) || round_off) && rows_meet(v, x)) {
      // Converged on the sets held: done if they are the solution's, else
      // the rows whose own branch differs are released (release()).
      Iterate free = x;
      bool stuck = false;
      const int released = release(v, x, free, round_off, stuck);
      if (released == 0) {
        out.converged = true;
        break;
      }
      x = std::move(free);
      if (stuck) rows(v, x, nullptr, true);
      last_full = -1;
      if (cold && ++stats_.rounds >= kMaxColdRounds) {
        out.reason = "ssn: the contact and friction sets of a cold solve did not settle in " +
                     std::to_string(kMaxColdRounds) + " rounds";
        break;
      }
      if (cold) round_start = iter + redone;
    }
  }
  out.iterations = stats_.iterations;
  // Above 1 the friction sets of a cold solve follow its velocity guess's
  // slip rates (c_T gamma_T against the bound): every row slipping, their
  // signs turning at each iteration. The ring at m = 1 stopped at its first
  // solve at 3, 10 and 100 and finished from 1e-3 to 1 (docs/decisions.md,
  // "ssn"); the failure of a cold solve names the parameter.
  if (!out.converged && cold && s_.c_tangential > kLargeTangential)
    out.reason += " (formulations.ssn.c_tangential = " + (std::ostringstream() << s_.c_tangential).str() +
                  " is above 1, where the friction sets follow the velocity guess: try the default 0.1)";
  out.residual = x.scale > 0 ? x.norm / x.scale : x.norm;
  if (!out.converged) return out;
  store(x, u);
  return out;
}

}  // namespace rpfem
