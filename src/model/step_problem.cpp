#include "model/step_problem.hpp"

#include <cmath>
#include <cstring>
#include <map>

#include "core/timing.hpp"
#include "fem/edge_weights.hpp"
#include "model/element_loop.hpp"
#include "model/scene.hpp"

namespace rpfem {

namespace {

// The same values to the bit (velocities a pass or kept terms were formed
// at against the ones asked for now).
template <class V>
bool same_bits(const V& a, const V& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(*a.data()) * a.size()) == 0;
}

// Sinks for the contact terms.
struct EnergySink : TermSink {
  double total = 0;
  void add(const Index*, int, double e, const double*, const double*) override { total += e; }
  bool needs_hessian() const override { return false; }
};
// The elements' forces at the contact's force nodes (TermSink::
// element_force), and for a tangent their Hessian rows: per node, its
// 2 x 2 blocks by column node.
struct NodeForces {
  std::map<Index, Vec2> force;
  std::map<Index, std::map<Index, Eigen::Matrix2d>> rows;
  Vec2 at(Index node) const {
    const auto it = force.find(node);
    return it == force.end() ? Vec2::Zero() : it->second;
  }
};
struct ForceSink : TermSink {
  std::vector<Vec2>& F;
  const NodeForces* nf;
  ForceSink(std::vector<Vec2>& f, const NodeForces* n) : F(f), nf(n) {}
  void add(const Index* nodes, int k, double, const double* g, const double*) override {
    for (int a = 0; a < k; ++a) F[nodes[a]] += Vec2(g[2 * a], g[2 * a + 1]);
  }
  bool needs_hessian() const override { return false; }
  Vec2 element_force(Index node) const override { return nf ? nf->at(node) : Vec2::Zero(); }
};
struct MatrixSink : TermSink {
  SparseAssembler& A;
  const NodeForces& nf;
  MatrixSink(SparseAssembler& a, const NodeForces& n) : A(a), nf(n) {}
  void add(const Index* nodes, int k, double, const double*, const double* H) override { A.add(nodes, k, H); }
  Vec2 element_force(Index node) const override { return nf.at(node); }
  void add_force_coupling(Index node, const Vec2& dir, const Index* nodes, int k, const double* coef) override {
    const auto it = nf.rows.find(node);
    if (it == nf.rows.end()) return;
    for (const auto& [col, K] : it->second) {
      const Eigen::RowVector2d r = dir.transpose() * K;  // d(dir . F_node)/dv_col
      for (int a = 0; a < k; ++a) {
        const Eigen::Matrix2d block = Vec2(coef[2 * a], coef[2 * a + 1]) * r;
        if (nodes[a] == col) {
          A.add(&col, 1, block.data());
          continue;
        }
        // As a two-node block (rows nodes[a], columns col; column-major).
        const Index pair[2] = {nodes[a], col};
        Eigen::Matrix4d B = Eigen::Matrix4d::Zero();
        B.block<2, 2>(0, 2) = block;
        A.add(pair, 2, B.data());
      }
    }
  }
};

}  // namespace

StepProblem::StepProblem(const StepView& view, const std::vector<std::array<double, 4>>& strain,
                         const std::vector<ElementMaterial>& materials, double epsdot_lim,
                         const std::vector<Vec2>& external_force, ContactFormulation& contact,
                         SolverWorkspace& ws)
    : view_(view), strain_(strain), materials_(materials), epsdot_lim_(epsdot_lim),
      fext_(external_force), contact_(contact), ws_(ws) {
  // The points' yield stresses, once for the problem's element passes.
  yield_.resize(strain_.size());
  for (std::size_t e = 0; e < strain_.size(); ++e)
    for (int q = 0; q < 4; ++q) yield_[e][q] = materials_[e].law->yield(strain_[e][q]);
}

void StepProblem::set_constraints(const std::vector<NodeConstraint>& constraints) {
  const Mesh& m = *view_.mesh;
  DofMap dofs(m.num_nodes(), constraints);
  // Kept terms stay where u maps to the same velocities (a contact pass
  // that changed no constraint) and the pattern stays.
  if (!(ws_.has_pattern && dofs == ws_.dofs)) terms_kept_ = false;
  ws_.dofs = std::move(dofs);
  std::vector<std::vector<Index>> couplings;
  contact_.couplings(view_, couplings);
  if (!ws_.has_pattern || ws_.layout != ws_.dofs.layout_hash() || couplings != ws_.couplings) {
    terms_kept_ = false;
    ws_.assembler.build(ws_.dofs, m.quads, couplings);
    ws_.couplings = std::move(couplings);
    ws_.layout = ws_.dofs.layout_hash();
    ws_.has_pattern = true;
    ++ws_.pattern_builds;
  }
}

RigidPlasticInput StepProblem::element_input(Index e, const std::vector<Vec2>& v) const {
  const auto& q = view_.mesh->quads[e];
  RigidPlasticInput in;
  for (int a = 0; a < 4; ++a) {
    in.X[a] = (*view_.x)[q[a]];
    in.v.segment<2>(2 * a) = v[q[a]];
  }
  in.strain = strain_[e];
  in.yield = yield_[e];
  in.law = materials_[e].law;
  in.alpha = materials_[e].alpha;
  in.regularization = materials_[e].regularization;
  in.geometry = view_.geometry;
  in.epsdot_lim = epsdot_lim_;
  in.viscous_floor = viscous_floor_;
  return in;
}

double StepProblem::energy(const Vec& u) const {
  auto t0 = Clock::now();
  std::vector<Vec2> v;
  ws_.dofs.expand(u, v);
  const Index ne = view_.mesh->num_elements();
  std::vector<double>& pi = ws_.element_values;
  pi.resize(ne);
  for_each_element(ne, ws_.threads, [&](Index el) { pi[el] = rigid_plastic_energy(element_input(el, v)); });
  double e = 0;
  for (Index el = 0; el < ne; ++el) e += pi[el];
  return energy_from_elements(v, e, t0);
}

double StepProblem::energy_from_elements(const std::vector<Vec2>& v, double elements, Clock::time_point t0) const {
  double e = elements;
  for (std::size_t i = 0; i < v.size(); ++i) e -= fext_[i].dot(v[i]);
  lap(t0, ws_.residual_seconds);
  EnergySink sink;
  contact_.add_terms(view_, v, sink);
  lap(t0, ws_.contact_seconds);
  return e + sink.total;
}

void StepProblem::element_pass(const std::vector<Vec2>& v, bool keep_terms, bool force_nodes) const {
  const Index ne = view_.mesh->num_elements();
  std::vector<Vec8>& grad = ws_.element_forces;
  std::vector<double>& pi = ws_.element_values;
  grad.resize(ne);
  pi.resize(ne);
  // Kept terms on a serial loop with no force nodes to read them go
  // straight into the matrix, in element order: tangent()'s scatter, the
  // same bits, without the terms' round trip through memory (30 MB at 1e5
  // unknowns). Not while a held factorization's solves read the matrix (a
  // chord iteration may still solve with it). Otherwise they are kept per
  // element.
  const bool fuse = keep_terms && !force_nodes && element_loop_is_serial(ne, ws_.threads) &&
                    !ws_.linear.solve_reads_matrix();
  if (keep_terms) terms_in_matrix_ = fuse, ++ws_.terms_writes;
  if (fuse) ws_.assembler.set_zero();
  if (keep_terms && !fuse) ws_.terms.resize(ne);
  for_each_element(ne, ws_.threads, [&](Index el) {
    ElementTerms local;
    ElementTerms& t = keep_terms && !fuse ? ws_.terms[el] : local;
    rigid_plastic_terms(element_input(el, v), keep_terms ? Tangent::Consistent : Tangent::None, t);
    grad[el] = t.grad;
    pi[el] = t.energy;
    if (fuse) ws_.assembler.add_quad(el, view_.mesh->quads[el].data(), t.hess.data());
  });
  double e = 0;
  for (Index el = 0; el < ne; ++el) e += pi[el];
  pass_energy_ = e;
  pass_v_ = v;
  pass_id_ = ++ws_.force_passes;
}

double StepProblem::nodal_forces(const std::vector<Vec2>& v, std::vector<Vec2>& F, double* element_energy,
                                 bool keep_terms) const {
  auto t0 = Clock::now();
  F.assign(v.size(), Vec2::Zero());
  const Index ne = view_.mesh->num_elements();
  std::vector<Index> nodes;
  contact_.force_nodes(view_, nodes);
  // The last pass's results where it was at these very velocities and
  // nothing has written the element forces since.
  const bool reuse = !keep_terms && pass_id_ != 0 && pass_id_ == ws_.force_passes && same_bits(pass_v_, v);
  if (reuse)
    ++ws_.force_passes_reused;
  else
    element_pass(v, keep_terms, !nodes.empty());
  const std::vector<Vec8>& grad = ws_.element_forces;
  if (element_energy) *element_energy = pass_energy_;
  double scale2 = 0;
  for (Index el = 0; el < ne; ++el) {
    const auto& q = view_.mesh->quads[el];
    for (int a = 0; a < 4; ++a) F[q[a]] += grad[el].segment<2>(2 * a);
    scale2 += grad[el].squaredNorm();
  }
  for (std::size_t i = 0; i < v.size(); ++i) F[i] -= fext_[i];
  lap(t0, ws_.residual_seconds);
  NodeForces nf;
  for (Index n : nodes) nf.force[n] = F[n];
  ForceSink sink(F, nodes.empty() ? nullptr : &nf);
  contact_.add_terms(view_, v, sink);
  lap(t0, ws_.contact_seconds);
  return std::max(std::sqrt(scale2), force_floor_);
}

namespace {

// The nodal forces in the reduced unknowns: R_k = T_k . F_node.
void reduce_forces(const DofMap& dofs, const std::vector<Vec2>& F, Vec& R) {
  R.setZero(dofs.num_free());
  for (Index i = 0; i < dofs.num_nodes(); ++i) {
    const NodeFrame& f = dofs.frame(i);
    for (int k = 0; k < f.nfree; ++k) R(f.dof[k]) = f.T.col(k).dot(F[i]);
  }
}

}  // namespace

bool StepProblem::kept_at(const Vec& u) const {
  return terms_writes_ == ws_.terms_writes && same_bits(terms_u_, u);
}

double StepProblem::forces_at(const Vec& u, std::vector<Vec2>& v, std::vector<Vec2>& F, double* element_energy) const {
  ws_.dofs.expand(u, v);
  // Terms kept at this very u already (a pass's start after its last
  // trial): the forces alone, which the last pass may give.
  const bool keep = keep_terms_ && !(terms_kept_ && kept_at(u));
  if (keep) terms_kept_ = false;  // ws_.terms are about to be overwritten
  const double scale = nodal_forces(v, F, element_energy, keep);
  if (keep) terms_u_ = u, terms_kept_ = true, terms_writes_ = ws_.terms_writes;
  return scale;
}

void StepProblem::residual(const Vec& u, Vec& R, double& scale) const {
  std::vector<Vec2> v, F;
  scale = forces_at(u, v, F, nullptr);
  reduce_forces(ws_.dofs, F, R);
}

double StepProblem::residual_energy(const Vec& u, Vec& R, double& scale) const {
  std::vector<Vec2> v, F;
  double elements = 0;
  scale = forces_at(u, v, F, &elements);
  reduce_forces(ws_.dofs, F, R);
  return energy_from_elements(v, elements, Clock::now());
}

const SpMat& StepProblem::tangent(const Vec& u, bool consistent) {
  auto t0 = Clock::now();
  std::vector<Vec2> v;
  ws_.dofs.expand(u, v);
  const Tangent kind = consistent ? Tangent::Consistent : Tangent::Secant;
  const Index ne = view_.mesh->num_elements();
  std::vector<ElementTerms>& terms = ws_.terms;
  // The contact's force nodes: their elements' force and, for a
  // consistent tangent, their Hessian rows, gathered in the scatter's
  // loop. A secant matrix is no derivative (K_s v = F): a secant
  // iteration leaves the force's dependence out (a fixed-point step on it).
  std::vector<Index> nodes;
  contact_.force_nodes(view_, nodes);
  // The terms a residual at this very u kept (keep_tangent_terms): the
  // same bits as computing them here; already scattered where
  // terms_in_matrix_ (never with force nodes, whose rows need them).
  const bool kept = consistent && terms_kept_ && kept_at(u) && !(terms_in_matrix_ && !nodes.empty());
  const bool scattered = kept && terms_in_matrix_;
  terms_kept_ = terms_in_matrix_ = false;
  ++ws_.terms_writes;
  ++(kept ? ws_.tangents_from_trials : ws_.tangent_passes);
  if (!kept) {
    terms.resize(ne);
    for_each_element(ne, ws_.threads, [&](Index el) { rigid_plastic_terms(element_input(el, v), kind, terms[el]); });
  }
  if (!scattered) ws_.assembler.set_zero();
  NodeForces nf;
  for (Index n : nodes) nf.force[n] = -fext_[n];
  if (consistent)
    for (Index n : nodes) nf.rows[n];
  for (Index el = 0; el < ne && !scattered; ++el) {
    const ElementTerms& t = terms[el];
    const auto& q = view_.mesh->quads[el];
    ws_.assembler.add_quad(el, q.data(), t.hess.data());
    if (nodes.empty()) continue;
    for (int a = 0; a < 4; ++a) {
      const auto f = nf.force.find(q[a]);
      if (f == nf.force.end()) continue;
      f->second += t.grad.segment<2>(2 * a);
      const auto it = nf.rows.find(q[a]);
      if (it == nf.rows.end()) continue;
      for (int b = 0; b < 4; ++b) {
        auto [blk, fresh] = it->second.try_emplace(q[b], Eigen::Matrix2d::Zero());
        blk->second += t.hess.block<2, 2>(2 * a, 2 * b);
      }
    }
  }
  lap(t0, ws_.assembly_seconds);
  MatrixSink sink(ws_.assembler, nf);
  contact_.add_terms(view_, v, sink);
  lap(t0, ws_.contact_seconds);
  return ws_.assembler.matrix();
}

bool StepProblem::solve(const Vec& u, bool consistent, const Vec& R, Vec& du) {
  const SpMat& A = tangent(u, consistent);
  if (!ws_.linear.factorize(A, contact_.tangent().symmetric, ws_.assembler.pattern_version())) return false;
  du = ws_.linear.solve(-R);
  return true;
}

void StepProblem::viscous_predictor(double rate, Vec& u) {
  viscous_floor_ = rate;
  forget_passes();
  Vec R, du;
  double scale;
  residual(u, R, scale);
  const bool ok = solve(u, false, R, du);  // linear problem: one solve is exact
  viscous_floor_ = 0;
  forget_passes();
  if (ok && du.allFinite()) u += du;
}

NewtonSystem StepProblem::newton_system() {
  NewtonSystem s;
  const TangentKind kind = contact_.tangent();
  if (kind.potential || kind.merit) s.energy = [this](const Vec& u) { return energy(u); };
  if (!kind.potential && kind.merit)
    s.anchor = [this](const Vec& u) {
      std::vector<Vec2> v;
      ws_.dofs.expand(u, v);
      contact_.anchor_merit(view_, v);
    };
  s.residual = [this](const Vec& u, Vec& R, double& scale) { residual(u, R, scale); };
  if (s.energy)
    s.residual_energy = [this](const Vec& u, Vec& R, double& scale) { return residual_energy(u, R, scale); };
  s.solve = [this](const Vec& u, bool c, const Vec& R, Vec& du) { return solve(u, c, R, du); };
  s.keep_tangent = [this](bool on) { keep_tangent_terms(on); };
  s.reuse = [this](const Vec& R, Vec& du) {
    if (!ws_.linear.holds(ws_.assembler.pattern_version(), R.size())) return false;
    du = ws_.linear.solve(-R);
    return true;
  };
  return s;
}

std::vector<Vec2> traction_forces(const Mesh& mesh, const std::vector<Vec2>& x, Geometry g,
                                  const std::vector<TractionLoad>& loads) {
  std::vector<Vec2> F(x.size(), Vec2::Zero());
  for (const auto& load : loads) {
    for (const Edge& e : mesh.sides.at(load.side)) {
      const Vec2 xa = x[e.a], xb = x[e.b];
      const Vec2 d = xb - xa;
      const double L = d.norm();
      const Vec2 n(d(1) / L, -d(0) / L);  // outward: body on the left of a -> b
      const Vec2 t = load.t - load.pressure * n;
      const auto w = edge_weights(xa, xb, g);  // int N_a dS
      F[e.a] += w[0] * t;
      F[e.b] += w[1] * t;
    }
  }
  return F;
}

}  // namespace rpfem
