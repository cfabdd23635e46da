#include "ipopt/ipopt_formulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fem/edge_weights.hpp"
#include "ipopt/friction_bounds.hpp"
#include "ipopt/step_nlp.hpp"
#include "model/boundary.hpp"
#include "model/step_problem.hpp"

namespace rpfem {

namespace {

// An instantaneous solve (StepView::moves false) anticipates no landing:
// only nodes within this fraction of the element size take part (as in
// `penalty`).
constexpr double kLandingTolerance = 1e-3;
// Kuhn-Tucker residuals (as checked after each solve) that make Ipopt's
// "acceptable" point a solution: penetration per element size, and the
// dual, complementarity and stationarity residuals (issue 5's targets).
constexpr double kAcceptPrimal = 1e-9;
constexpr double kAcceptKkt = 1e-8;
// Ipopt's complementarity tolerance as a fraction of kAcceptKkt (in the
// checked measure's units).
constexpr double kComplTolFactor = 0.1;

}  // namespace

IpoptContact::IpoptContact(const Scene& scene, CaseSection settings) : scene_(scene) {
  if (scene.contact_pairs.empty())
    throw InputError(scene.file + ": formulation 'ipopt' needs at least one [[contact_pairs]] entry");
  opt_.tol = settings.real("tol", 1e-10, Range::positive(), "Ipopt's tol (scaled NLP error)");
  opt_.bound_relax_factor =
      settings.real("bound_relax_factor", 1e-10, Range::nonnegative(), "Ipopt's relaxation of the contact bounds");
  opt_.max_iter = settings.integer("max_iter", 500, 1, 100000);
  opt_.mu_strategy = settings.text("mu_strategy", "monotone", {"monotone", "adaptive"});
  opt_.linear_solver = settings.text("linear_solver", "mumps", {"mumps"});
  opt_.print_level = settings.integer("print_level", 0, 0, 12);
  opt_.mu_init = settings.real("mu_init", 1e-6, Range::positive(), "Ipopt's initial barrier parameter");
  friction_tol_ = settings.real("friction_tolerance", 1e-6, Range::positive(),
                                "relative change of the friction bounds that ends the fixed point");
  last_force_.assign(scene.mesh.x.size(), 0.0);
  capture_ = settings.real("capture", 1.0, Range::positive(), "search reach, relative to the mean master edge length");
  speed_scale_ = scene.largest_speed();
  round_off_force_ = scene.solver.newton.tol_force;
  if (!(speed_scale_ > 0)) throw InputError(scene.file + ": formulation 'ipopt' scales by the largest prescribed speed, but nothing moves");
  sigma_ref_ = INFINITY;
  for (const auto& b : scene.bodies) sigma_ref_ = std::min(sigma_ref_, b.law.yield(0.0));
  sym_tol_ = 1e-9 * scene.mesh.size();
  // One application for the run: its options are read once, each solve
  // hands it a new NLP.
  app_ = IpoptApplicationFactory();
  auto& o = *app_->Options();
  o.SetStringValue("sb", "yes");
  o.SetIntegerValue("print_level", opt_.print_level);
  o.SetNumericValue("tol", opt_.tol);
  o.SetNumericValue("bound_relax_factor", opt_.bound_relax_factor);
  o.SetIntegerValue("max_iter", opt_.max_iter);
  o.SetStringValue("mu_strategy", opt_.mu_strategy);
  o.SetNumericValue("mu_init", opt_.mu_init);
  o.SetStringValue("linear_solver", opt_.linear_solver);
  o.SetStringValue("jac_d_constant", "yes");
  o.SetStringValue("nlp_scaling_method", "user-scaling");
  if (app_->Initialize() != Ipopt::Solve_Succeeded)
    throw InputError(scene.file + ": [formulations.ipopt]: Ipopt refused the options");
  for (const auto& pair : scene.contact_pairs) {
    Interface f;
    f.friction = pair.with_die() ? scene.dies[pair.die_id].friction : pair.friction;
    const ContactSurface s0 = ContactSurface::from_sides(scene.mesh, pair.sides);
    if (pair.with_die()) {
      f.name = pair.body + "-" + pair.die;
      f.die = pair.die_id;
      f.slave = s0;
    } else {
      f.name = pair.body + "-" + pair.with_body;
      const ContactSurface s1 = ContactSurface::from_sides(scene.mesh, pair.with_sides);
      const bool first_finer = mean_edge_length(scene.mesh.x, s0) <= mean_edge_length(scene.mesh.x, s1);
      f.slave = first_finer ? s0 : s1;
      f.master = first_finer ? s1 : s0;
    }
    f.h = mean_edge_length(scene.mesh.x, f.slave);
    for (const Edge& e : f.slave.edges) {
      const auto w = edge_weights(scene.mesh.x[e.a], scene.mesh.x[e.b], scene.geometry);
      area_ += w[0] + w[1];
    }
    ifaces_.push_back(std::move(f));
  }
}

void IpoptContact::begin_step(const StepView& v) {
  const auto& x = *v.x;
  pairs_.clear();
  for (int i = 0; i < static_cast<int>(ifaces_.size()); ++i) {
    const Interface& f = ifaces_[i];
    std::vector<std::optional<SegmentHit>> hits;
    if (f.die < 0) {
      const double capture = capture_ * mean_edge_length(x, f.master);
      hits = find_segments(x, f.slave, f.master, SegmentGrid(x, f.master, capture), capture);
    }
    // The slave nodes' lumped contact areas.
    std::vector<double> w(f.slave.nodes.size(), 0.0);
    for (const Edge& e : f.slave.edges) {
      const auto ew = edge_weights(x[e.a], x[e.b], v.geometry);
      w[f.slave.local(e.a)] += ew[0], w[f.slave.local(e.b)] += ew[1];
    }
    for (int l = 0; l < static_cast<int>(f.slave.nodes.size()); ++l) {
      const Index n = f.slave.nodes[l];
      Pair p;
      p.iface = i;
      p.h = f.h;
      p.weight = w[l];
      if (f.die >= 0) {
        p.kin = die_pair(scene_.dies[f.die], n, x, v.time);
      } else {
        if (!hits[l]) continue;
        p.kin = segment_pair(n, f.master.edges[hits[l]->edge], *hits[l]);
      }
      if (v.x_from && v.x_from != v.x)
        set_gap_from(p.kin, x, *v.x_from, v.time, v.time_from, f.die >= 0 ? &scene_.dies[f.die] : nullptr);
      if (!v.moves) {
        if (p.kin.gap0 > kLandingTolerance * f.h) continue;
        p.kin.gap_from = std::min(p.kin.gap_from, 0.0);
      }
      pairs_.push_back(p);
    }
  }
  // The first bounds of the step: from the last step's forces.
  set_bounds(v, last_force_);
}

void IpoptContact::set_bounds(const StepView& v, const std::vector<double>& force) {
  // k w over the slave's edges with both ends pressing (the contact area
  // the sticking bound acts on, as in `direct` and `penalty`).
  const auto& x = *v.x;
  std::vector<double> kw(x.size(), 0.0);
  for (const Interface& f : ifaces_) {
    if (f.friction.kind == FrictionLaw::Kind::None) continue;
    for (const Edge& e : f.slave.edges) {
      if (!(force[e.a] > 0 && force[e.b] > 0)) continue;
      const auto ew = edge_weights(x[e.a], x[e.b], v.geometry);
      const double k = v.flow_stress ? (*v.flow_stress)[e.element] / std::sqrt(3.0) : 0.0;  // von Mises
      kw[e.a] += k * ew[0], kw[e.b] += k * ew[1];
    }
  }
  for (Pair& p : pairs_) {
    const Index s = p.kin.nodes[0];
    p.kw = kw[s];
    p.bound = friction_bound(ifaces_[p.iface].friction, force[s], p.kw);
  }
}

std::optional<SolveOutcome> IpoptContact::solve(const StepView& v, StepProblem& problem, Vec& u) {
  // Rows: gamma_N(u) + g_from / dt >= 0 with v_a = T_a u_a + p_a.
  const DofMap& dofs = problem.dofs();
  const double inv_dt = v.dt > 0 ? 1.0 / v.dt : 0.0;
  std::vector<LinearRow> rows;
  std::vector<int> row_pair;
  for (int j = 0; j < static_cast<int>(pairs_.size()); ++j) {
    const PairKinematics& k = pairs_[j].kin;
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
    row_pair.push_back(j);
  }
  // Ipopt's absolute complementarity tolerance (N mm/s) comes from the
  // element forces of the last solve (at the run's first solve: of the
  // point Ipopt starts from). When the forces at the solution are smaller
  // (a first point contact) and the checked complementarity misses
  // kAcceptKkt, it solves once more from its solution with the tolerance
  // of the solution's forces.
  if (!(last_scale_ > 0)) {
    Vec R;
    problem.residual(u, R, last_scale_);
  }
  const auto finite = [&](const NlpOutcome& o) { return o.u.size() == u.size() && o.u.allFinite(); };
  NlpOutcome out = optimize(problem, rows, u, last_scale_);
  SolveOutcome result;
  result.iterations = out.iterations;
  if (finite(out)) {
    last_scale_ = measure(v, problem, rows, row_pair, out);
    if (out.status == Ipopt::SUCCESS && kkt_.complementarity > kAcceptKkt) {
      const Vec from = out.u;
      out = optimize(problem, rows, from, last_scale_);
      result.iterations += out.iterations;
      if (finite(out)) last_scale_ = measure(v, problem, rows, row_pair, out);
    }
  }
  rows_ = static_cast<int>(rows.size());
  if (!finite(out)) {
    result.reason = "Ipopt: " + ipopt_status_text(out.status) + " (no finite solution)";
    return result;
  }
  result.residual = kkt_.stationarity;
  // Ipopt's stalls, at its "acceptable" point or at a tiny step (its
  // correction at round-off, as Newton's round-off floor in
  // solver/newton.cpp), are taken when the contact conditions hold to
  // kAcceptKkt and stationarity is within the floor Newton accepts, 100
  // tol_force (a virtual rigid body's terms leave 1e-6; kkt_round_off
  // shows the residual's own evaluation noise there).
  const bool contact_ok = kkt_.primal <= kAcceptPrimal && kkt_.dual <= kAcceptKkt && kkt_.complementarity <= kAcceptKkt;
  const bool stalled = out.status == Ipopt::STOP_AT_ACCEPTABLE_POINT || out.status == Ipopt::STOP_AT_TINY_STEP;
  const bool acceptable = contact_ok && stalled && kkt_.stationarity <= 100 * round_off_force_;
  if (out.status != Ipopt::SUCCESS && !acceptable) {
    char buf[200];
    std::snprintf(buf, sizeof buf, " (%d iterations; Kuhn-Tucker residuals: primal %.1e, dual %.1e, complementarity "
                  "%.1e, stationarity %.1e)", out.iterations, kkt_.primal, kkt_.dual, kkt_.complementarity,
                  kkt_.stationarity);
    result.reason = "Ipopt: " + ipopt_status_text(out.status) + buf;
    return result;
  }
  u = out.u;
  result.converged = true;
  return result;
}

NlpOutcome IpoptContact::optimize(StepProblem& problem, const std::vector<LinearRow>& rows, const Vec& from,
                                  double force) {
  // Force scale of the objective: the softest body's yield stress over the
  // whole slave surface (what the contact could carry; a point contact at
  // the start carries far less, and its own load would put round-off
  // above tol).
  const double force_scale = std::max(sigma_ref_ * area_, 1e-12);
  if (force > 0) app_->Options()->SetNumericValue("compl_inf_tol", kComplTolFactor * kAcceptKkt * force * speed_scale_);
  NlpOutcome out;
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = new StepNlp(problem, rows, from, force_scale, speed_scale_, out);
  app_->OptimizeTNLP(nlp);
  return out;
}

double IpoptContact::measure(const StepView& v, const StepProblem& problem, const std::vector<LinearRow>& rows,
                             const std::vector<int>& row_pair, const NlpOutcome& out) {
  // The Kuhn-Tucker conditions (paper eq. 6), checked here.
  Vec R;
  double scale = 0;
  problem.residual(out.u, R, scale);
  if (!(scale > 0)) scale = 1;
  Vec stat = R;
  for (auto& p : pairs_) p.force = 0, p.end_gap = p.kin.gap_from;
  kkt_ = Kkt{};
  active_ = 0;
  max_penetration_ = 0;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const double lambda = out.lambda[j];
    double value = 0;
    for (const auto& [dof, a] : rows[j].terms) {
      value += a * out.u[dof];
      stat[dof] += a * lambda;
    }
    Pair& p = pairs_[row_pair[j]];
    const double slack = value - rows[j].lower;  // mm/s
    p.force = -lambda;
    p.end_gap = v.dt * slack;
    active_ += pressing(p) ? 1 : 0;
    const double pen = std::max(0.0, -p.end_gap);
    max_penetration_ = std::max(max_penetration_, pen);
    kkt_.primal = std::max(kkt_.primal, pen / p.h);
    kkt_.dual = std::max(kkt_.dual, std::max(0.0, -p.force) / scale);
    kkt_.complementarity = std::max(kkt_.complementarity, std::abs(p.force * slack) / (scale * speed_scale_));
  }
  kkt_.stationarity = stat.norm() / scale;
  // The residual's own round-off: R at u with every component moved by one
  // unit in the last place (signs from a fixed hash), over the same scale.
  // A stationarity within a small multiple of this is the floor of
  // evaluating R in double precision, not a solver shortfall.
  {
    Vec u1 = out.u, R1;
    for (Index i = 0; i < u1.size(); ++i) {
      const double ulp = std::nextafter(std::abs(u1[i]), INFINITY) - std::abs(u1[i]);
      u1[i] += ((i * 2654435761u) >> 7) % 2 ? ulp : -ulp;
    }
    double s1 = 0;
    problem.residual(u1, R1, s1);
    kkt_.round_off = (R1 - R).norm() / scale;
  }
  return scale;
}

void IpoptContact::couplings(const StepView&, std::vector<std::vector<Index>>& out) const {
  for (const Pair& p : pairs_)
    if (p.kin.k > 1 && ifaces_[p.iface].friction.kind != FrictionLaw::Kind::None)
      out.push_back({p.kin.nodes.begin(), p.kin.nodes.begin() + p.kin.k});
}

void IpoptContact::add_terms(const StepView&, const std::vector<Vec2>& vel, TermSink& sink) const {
  for (const Pair& p : pairs_) {
    if (!(p.bound > 0)) continue;
    std::array<Vec2, 3> v{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
    for (int a = 0; a < p.kin.k; ++a) v[a] = vel[p.kin.nodes[a]];
    const FrictionTerm t = friction_term(p.kin, p.bound, ifaces_[p.iface].friction.a_relative * speed_scale_, v);
    sink.add(p.kin.nodes.data(), p.kin.k, t.energy, t.grad.data(), t.hess.data());
  }
}

StepCheck IpoptContact::check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>&) {
  // The friction force of this solve, then the fixed point on the bounds.
  StepCheck out;
  std::vector<double> force(vel.size(), 0.0), before(pairs_.size());
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    Pair& p = pairs_[i];
    const FrictionLaw& law = ifaces_[p.iface].friction;
    if (p.bound > 0) p.friction = -p.bound * arctan_potential(slip_rate(p.kin, vel), law.a_relative * speed_scale_).dpsi;
    if (pressing(p)) force[p.kin.nodes[0]] = std::max(force[p.kin.nodes[0]], p.force);
    before[i] = p.bound;
  }
  set_bounds(v, force);
  double largest = 0, change = 0;
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    largest = std::max({largest, before[i], pairs_[i].bound});
    change = std::max(change, std::abs(pairs_[i].bound - before[i]));
  }
  friction_change_ = largest > 0 ? change / largest : 0.0;
  out.resolve = friction_change_ > friction_tol_;
  return out;
}

void IpoptContact::advance(const StepView&, const std::vector<Vec2>&) {
  // The next step's first bounds come from this step's forces.
  std::fill(last_force_.begin(), last_force_.end(), 0.0);
  for (const Pair& p : pairs_)
    if (pressing(p)) last_force_[p.kin.nodes[0]] = std::max(last_force_[p.kin.nodes[0]], p.force);
}

std::optional<double> IpoptContact::reference_speed(const std::string& name) const {
  for (const auto& d : scene_.dies)
    if (d.name == name) return d.motion.max_speed();
  return std::nullopt;
}

std::array<Vec2, 3> IpoptContact::pair_forces(const Pair& p) const {
  // The row's force on the bodies, -lambda d(row)/dv_a = N c_a n, and the
  // friction force along t.
  const Vec2 t(-p.kin.n(1), p.kin.n(0));
  std::array<Vec2, 3> f{Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  for (int a = 0; a < p.kin.k; ++a) f[a] = p.kin.c[a] * (p.force * p.kin.n + p.friction * t);
  return f;
}

void IpoptContact::contact_forces(const StepView&, const std::vector<Vec2>& vel, const std::vector<Vec2>&,
                                  std::vector<Vec2>& out) const {
  out.assign(vel.size(), Vec2::Zero());
  for (const Pair& p : pairs_) {
    const auto f = pair_forces(p);
    for (int a = 0; a < p.kin.k; ++a) out[p.kin.nodes[a]] += f[a];
  }
}

std::vector<std::string> IpoptContact::load_names() const {
  std::vector<std::string> n;
  for (const auto& d : scene_.dies) n.push_back(d.name);
  return n;
}

std::vector<Vec2> IpoptContact::loads(const StepView& v, const std::vector<Vec2>&) const {
  // A die's load: the force it exerts on the bodies (as in `direct`).
  std::vector<Vec2> out;
  for (int d = 0; d < static_cast<int>(scene_.dies.size()); ++d) {
    Vec2 sum = Vec2::Zero();
    std::vector<Index> nodes;
    for (const Pair& p : pairs_)
      if (ifaces_[p.iface].die == d && p.force != 0) {
        sum += pair_forces(p)[0];
        nodes.push_back(p.kin.nodes[0]);
      }
    out.push_back(sum.cwiseProduct(symmetry_load_factor(scene_.symmetry, *v.x, nodes, sym_tol_)));
  }
  return out;
}

void IpoptContact::node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const {
  auto& pr = out["contact_pressure"];
  auto& sh = out["contact_shear"];
  auto& gap = out["contact_gap"];
  for (auto* f : {&pr, &sh, &gap}) f->assign(v.x->size(), 0.0);
  for (const Pair& p : pairs_) {
    const Index s = p.kin.nodes[0];
    gap[s] = p.kin.gap0;
    if (p.weight > 0) pr[s] += p.force / p.weight, sh[s] += p.friction / p.weight;
  }
}

std::vector<std::string> IpoptContact::report_names() const {
  return {"contact_candidates", "contact_pairs", "max_penetration", "max_penetration_rel",
          "kkt_primal", "kkt_dual", "kkt_complementarity", "kkt_stationarity", "kkt_round_off", "friction_change"};
}

std::vector<double> IpoptContact::report() const {
  return {static_cast<double>(rows_), static_cast<double>(active_), max_penetration_, kkt_.primal,
          kkt_.primal, kkt_.dual, kkt_.complementarity, kkt_.stationarity, kkt_.round_off, friction_change_};
}

std::vector<NamedValue> IpoptContact::derived() const {
  std::vector<NamedValue> out{{"ipopt.speed_scale_mm_s", speed_scale_}};
  for (const auto& f : ifaces_) out.push_back({"ipopt." + f.name + ".element_size_mm", f.h});
  return out;
}

}  // namespace rpfem
