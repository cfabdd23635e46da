// The linear algebra of one ssn Newton step (ssn_step_solver.hpp): the
// saddle-point system's generalized Jacobian and its sparse LU, or the
// rows condensed onto their nodes and K solved by CHOLMOD (the augmented
// Lagrangian on K: ssn_augmented_step.cpp).
#include "ssn/ssn_step_solver.hpp"

#include <algorithm>
#include <map>

#include "core/timing.hpp"

namespace rpfem {

namespace {

// The multiplier block's diagonal where the functions have none (N s/mm
// per N: against c ~ sigma w / v of 1e3 to 1e6).
constexpr double kRegularization = 1e-8;

}  // namespace

// The hash of a sparse matrix's pattern (FNV-1a over its index arrays).
std::uint64_t SsnStepSolver::pattern_hash(const SpMat& A) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t x) { h = (h ^ x) * 1099511628211ull; };
  mix(static_cast<std::uint64_t>(A.rows()));
  for (Eigen::Index c = 0; c <= A.outerSize(); ++c) mix(static_cast<std::uint64_t>(A.outerIndexPtr()[c]));
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k) mix(static_cast<std::uint64_t>(A.innerIndexPtr()[k]));
  return h;
}

SpMat SsnStepSolver::jacobian(const SpMat& K, const Iterate& it) const {
  const Index n = K.rows();
  const std::size_t m = red_.size();
  std::vector<Eigen::Triplet<double, int>> trip;
  trip.reserve(K.nonZeros() + 8 * m * 8);
  for (Eigen::Index c = 0; c < K.outerSize(); ++c)
    for (SpMat::InnerIterator e(K, c); e; ++e) trip.emplace_back(e.row(), e.col(), e.value());
  // Every row's entries are in the pattern whatever its set (zeros kept),
  // so the pattern, and the LU's analysis, hold over the solve.
  for (std::size_t j = 0; j < m; ++j) {
    const Reduced& rr = red_[j];
    const RowNcp& q = it.ncp[j];
    const int N = static_cast<int>(n + 2 * j), T = N + 1;
    for (const auto& [d, w] : rr.an) {
      trip.emplace_back(d, N, -w);
      trip.emplace_back(N, d, q.dcn_dr * w);
      trip.emplace_back(T, d, q.dct_dr * w);
    }
    for (const auto& [d, w] : rr.at) {
      trip.emplace_back(d, T, -w);
      trip.emplace_back(T, d, q.dct_ds * w);
    }
    // A row in contact (sticking) has no diagonal in its multiplier's
    // column; kRegularization there keeps the system solvable where rows
    // are linearly dependent (a body row between two nodes each held on a
    // die): the Newton matrix only, F is unchanged, so the solution is.
    trip.emplace_back(N, N, q.dcn_dln != 0 ? q.dcn_dln : -kRegularization);
    trip.emplace_back(T, N, q.dct_dln);
    trip.emplace_back(T, T, q.dct_dlt != 0 ? q.dct_dlt : -kRegularization);
  }
  const Index size = n + 2 * static_cast<Index>(m);
  SpMat J(size, size);
  J.setFromTriplets(trip.begin(), trip.end());
  return J;
}

bool SsnStepSolver::condensable(const Iterate& it) const {
  // Rows of one node against a die with both its directions free (T = I),
  // on a branch whose multipliers are the node's reactions or known
  // forces: open, sticking, or slipping under a fixed bound.
  if (!s_.condense) return false;
  std::map<Index, int> on;
  for (std::size_t j = 0; j < red_.size(); ++j) {
    const Reduced& rr = red_[j];
    const RowNcp& q = it.ncp[j];
    // Two free directions, or one (a node on the axis or a symmetry plane,
    // held frictionless: one_direction).
    const bool two = rr.an.size() == 2 && !rr.one_direction, one = rr.an.size() == 1 && rr.one_direction;
    if (rr.die_node < 0 || !(two || one) || q.grazing) return false;
    if (q.active && !q.stick && (q.dct_dln != 0 || q.dct_dr != 0)) return false;  // Coulomb's bound follows N
    if (q.active && ++on[rr.die_node] > 1) return false;
  }
  return true;
}

bool SsnStepSolver::rotate_in_place(SpMat& A, const std::vector<int>& row_of) const {
  // A = Q^T A Q, Q the identity but at the rotated nodes, whose dofs ix, iy
  // it takes to their frame's (n, t): column ix of A Q is n_x A(:, ix) +
  // n_y A(:, iy), column iy t_x A(:, ix) + t_y A(:, iy), and the rows
  // likewise. In place where each such node's two columns, and so (the
  // tangent's pattern being symmetric) its two rows in every column, share
  // one pattern; otherwise false and A is not to be used.
  if (!A.isCompressed()) return false;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  double* val = A.valuePtr();
  std::vector<std::size_t> nodes;  // rows of the solve rotated
  for (std::size_t j = 0; j < red_.size(); ++j) {
    const Reduced& rr = red_[j];
    if (rr.an.size() != 2 || row_of[rr.an[0].first] != static_cast<int>(j)) continue;
    const Index ix = rr.an[0].first, iy = rr.an[1].first;
    if (outer[ix + 1] - outer[ix] != outer[iy + 1] - outer[iy] ||
        !std::equal(inner + outer[ix], inner + outer[ix + 1], inner + outer[iy]))
      return false;
    nodes.push_back(j);
  }
  for (const std::size_t j : nodes) {
    const Reduced& rr = red_[j];
    const Index ix = rr.an[0].first, iy = rr.an[1].first;
    const double nx = rr.an[0].second, ny = rr.an[1].second, tx = rr.at[0].second, ty = rr.at[1].second;
    double *a = val + outer[ix], *b = val + outer[iy];
    for (int k = 0; k < outer[ix + 1] - outer[ix]; ++k) {
      const double x = a[k], y = b[k];
      a[k] = nx * x + ny * y, b[k] = tx * x + ty * y;
    }
  }
  for (Eigen::Index c = 0; c < A.outerSize(); ++c) {
    const int *first = inner + outer[c], *last = inner + outer[c + 1];
    for (const int* p = first; p != last; ++p) {
      const int j = row_of[*p];
      if (j < 0 || *p != red_[j].an[0].first) continue;
      const Reduced& rr = red_[j];
      const int* q = std::lower_bound(first, last, static_cast<int>(rr.an[1].first));
      if (q == last || *q != rr.an[1].first) return false;
      double &x = val[p - inner], &y = val[q - inner];
      const double x0 = x, y0 = y;
      x = rr.an[0].second * x0 + rr.an[1].second * y0;
      y = rr.at[0].second * x0 + rr.at[1].second * y0;
    }
  }
  return true;
}

bool SsnStepSolver::condensed_step(const SpMat& K, const Iterate& it, Vec& dx) {
  // The rows' multipliers condensed (Popp et al. 2010; Wohlmuth 2011): at
  // a node pressing on a die, the step's normal velocity is prescribed
  // (C_N = c_N r: n . du = -r), and sticking its tangential one too
  // (t . du = -gamma_T); the forces are the reactions there, or a
  // slipping row's bound g s, a known force. K in the nodes' (n, t)
  // frames with the prescribed directions eliminated stays symmetric
  // positive definite: CHOLMOD.
  const Index n = K.rows();
  const std::size_t m = red_.size();
  // Per dof: its node's frame column (n or t) where rotated.
  std::vector<int> row_of(n, -1);
  for (std::size_t j = 0; j < m; ++j)
    if (it.ncp[j].active && red_[j].an.size() == 2)
      row_of[red_[j].an[0].first] = row_of[red_[j].an[1].first] = static_cast<int>(j);
  // The dofs' local coordinates xi = Q^T du: at a rotated node dof ix holds
  // xi_n and iy xi_t; Q's entries (global dof d, local dof p).
  auto q_entries = [&](Index d, std::pair<Index, double>* out) {
    const int j = row_of[d];
    if (j < 0) return out[0] = {d, 1.0}, 1;
    const Reduced& rr = red_[j];
    const int c = d == rr.an[0].first ? 0 : 1;  // the global component
    out[0] = {rr.an[0].first, rr.an[c].second};  // n's component
    out[1] = {rr.an[1].first, rr.at[c].second};  // t's component
    return 2;
  };
  SpMat A = K;
  if (!rotate_in_place(A, row_of)) {
    std::vector<Eigen::Triplet<double, int>> trip;
    trip.reserve(2 * K.nonZeros());
    std::pair<Index, double> qi[2], qj[2];
    for (Eigen::Index c = 0; c < K.outerSize(); ++c) {
      const int nj = q_entries(c, qj);
      for (SpMat::InnerIterator e(K, c); e; ++e) {
        const int ni = q_entries(e.row(), qi);
        for (int a = 0; a < ni; ++a)
          for (int b = 0; b < nj; ++b) trip.emplace_back(qi[a].first, qj[b].first, qi[a].second * e.value() * qj[b].second);
      }
    }
    A = SpMat(n, n);
    A.setFromTriplets(trip.begin(), trip.end());
  }
  // The right-hand side -R plus the slipping rows' known forces, in the
  // local coordinates.
  Vec b = -it.R;
  std::vector<double> lt_new(m, 0.0);
  for (std::size_t j = 0; j < m; ++j) {
    const RowNcp& q = it.ncp[j];
    if (!q.active || q.stick || red_[j].an.size() == 1) continue;
    lt_new[j] = q.g * q.sign;
    for (const auto& [d, w] : red_[j].at) b[d] += lt_new[j] * w;
  }
  // y = Q^T x (to_local) or Q x at the rotated nodes: Q's columns there
  // are n and t.
  const auto rotate = [&](const Vec& x, bool to_local) {
    Vec y = x;
    for (std::size_t j = 0; j < m; ++j) {
      if (!it.ncp[j].active || red_[j].an.size() == 1) continue;
      const Reduced& rr = red_[j];
      const Index ix = rr.an[0].first, iy = rr.an[1].first;
      const double nx = rr.an[0].second, ny = rr.an[1].second, tx = rr.at[0].second, ty = rr.at[1].second;
      y[ix] = to_local ? nx * x[ix] + ny * x[iy] : nx * x[ix] + tx * x[iy];
      y[iy] = to_local ? tx * x[ix] + ty * x[iy] : ny * x[ix] + ty * x[iy];
    }
    return y;
  };
  Vec bl = rotate(b, true);
  // Prescribed local dofs and their values.
  std::vector<char> fixed(n, 0);
  Vec value = Vec::Zero(n);
  for (std::size_t j = 0; j < m; ++j) {
    const RowNcp& q = it.ncp[j];
    if (!q.active) continue;
    if (red_[j].an.size() == 1) {  // its one free dof moves the gap: a_N du = -r
      const auto [d, w] = red_[j].an[0];
      fixed[d] = 1, value[d] = -it.r[j] / w;
      continue;
    }
    const Index pn = red_[j].an[0].first, pt = red_[j].an[1].first;
    fixed[pn] = 1, value[pn] = -it.r[j];
    if (q.stick) fixed[pt] = 1, value[pt] = -it.g[j];
  }
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (SpMat::InnerIterator e(A, c); e; ++e) {
      const Index i = e.row();
      if (fixed[c] && !fixed[i]) bl[i] -= e.value() * value[c];
      if ((fixed[c] || fixed[i]) && i != c) e.valueRef() = 0;
    }
  for (Index p = 0; p < n; ++p)
    if (fixed[p]) bl[p] = A.coeff(p, p) * value[p];
  // A's pattern is K's, fixed within a solve: hashed at its first step.
  if (!condensed_hashed_) {
    const std::uint64_t h = pattern_hash(A);
    if (h != condensed_hash_) condensed_hash_ = h, ++condensed_version_;
    condensed_hashed_ = true;
  }
  Vec xi;
  {
    ScopedSeconds timing(stats_.factor_seconds);
    if (!cholesky_.factorize(A, true, condensed_version_)) return false;
    xi = cholesky_.solve(bl);
  }
  // du = Q xi, then the reactions from the nodes' equilibrium.
  const Vec du = rotate(xi, false);
  const Vec res = K * du + it.R;  // the elements' force after the step
  dx.resize(n + 2 * static_cast<Index>(m));
  dx.head(n) = du;
  for (std::size_t j = 0; j < m; ++j) {
    const RowNcp& q = it.ncp[j];
    double ln = 0, lt = 0;
    if (q.active && red_[j].an.size() == 1) {
      ln = res[red_[j].an[0].first] / red_[j].an[0].second;
    } else if (q.active) {
      const Reduced& rr = red_[j];
      const Index dx_ = rr.an[0].first, dy_ = rr.an[1].first;
      ln = rr.an[0].second * res[dx_] + rr.an[1].second * res[dy_];
      lt = q.stick ? rr.at[0].second * res[dx_] + rr.at[1].second * res[dy_] : lt_new[j];
    }
    dx[n + 2 * j] = ln - it.ln[j];
    dx[n + 2 * j + 1] = lt - it.lt[j];
  }
  ++stats_.condensed;
  return dx.allFinite();
}

bool SsnStepSolver::newton_step(const SpMat& K, const Iterate& it, Vec& dx) {
  if (condensable(it)) return condensed_step(K, it, dx);
  if (s_.augmented && augmented_step(K, it, dx)) return true;
  const SpMat J = jacobian(K, it);
  // Every row's entries are in J's pattern, and K's is fixed within a
  // solve: hashed at its first step.
  if (!saddle_hashed_) {
    const std::uint64_t h = pattern_hash(J);
    if (h != pattern_hash_) pattern_hash_ = h, ++pattern_version_;
    saddle_hashed_ = true;
  }
  {
    ScopedSeconds timing(stats_.factor_seconds);
    if (!lu_.factorize(J, false, pattern_version_)) return false;
    dx = lu_.solve(-it.F);
  }
  return dx.allFinite();
}

}  // namespace rpfem
