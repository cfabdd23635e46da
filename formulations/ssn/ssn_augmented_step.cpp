// The ssn Newton step for rows that do not condense onto single nodes
// (rows between bodies, mortar rows) when every row's functions are either
// an equation on the velocities alone (a row in contact: a_N . du = g_N; a
// sticking row: a_T . du = g_T) or on its own multiplier alone (open,
// frictionless, or slipping under the friction factor's fixed bound): the
// step's system (ssn_step_solver.hpp) is then
//   K du - A_E^T dl_E = b,   A_E du = g,
// with b the momentum rows' right side less the known multipliers' forces.
// Solved by the augmented Lagrangian (method of multipliers) on it,
//   (K + rho A_E^T A_E) du_k = b + rho A_E^T g + A_E^T l_k,
//   l_{k+1} = l_k + rho (g - A_E du_k),
// (Hestenes 1969, Powell 1969; Fortin and Glowinski 1983, ch. 1): one
// Cholesky factorization (CHOLMOD, as the kernel's Newton) and a few solves
// with it, exact at convergence (l_k -> dl_E). K + rho A_E^T A_E is
// positive definite where the rows hold what K alone does not (Test I's
// lower sphere, held by contact only): the saddle-point system's sparse LU
// (KLU) was 55 % of that run. Coulomb's slipping rows (their bound follows
// lambda_N and r) and grazing rows keep the LU.
#include "ssn/ssn_step_solver.hpp"

#include <algorithm>
#include <cmath>

#include "core/timing.hpp"

namespace rpfem {

namespace {

// rho relative to K's mean diagonal over the rows' mean |a|^2: the
// multipliers' error contracts by about 1 / (1 + kRho) per solve.
constexpr double kRho = 1e4;
constexpr int kMaxSolves = 30;
// Each row's |a . du - g| against |g| + |a| |du|_inf at convergence: the
// saddle-point LU's round-off (rho adds about four digits to it).
constexpr double kConverged = 1e-11;

// One function of a row: an equation on du along `a` (equality) with its
// multiplier unknown, or its multiplier's step known.
struct RowFunction {
  const std::vector<std::pair<Index, double>>* a = nullptr;
  bool equality = false;
  double value = 0;  // g (equality) or the multiplier's step
};

}  // namespace

bool SsnStepSolver::augmented_step(const SpMat& K, const Iterate& it, Vec& dx) {
  const Index n = K.rows();
  const std::size_t m = red_.size();
  if (m == 0) return false;
  const Vec& F = it.F;
  std::vector<RowFunction> f(2 * m);
  for (std::size_t j = 0; j < m; ++j) {
    const RowNcp& q = it.ncp[j];
    const double cn = F[n + 2 * j], ct = F[n + 2 * j + 1];
    if (q.grazing || q.dct_dln != 0 || q.dct_dr != 0) return false;
    RowFunction& fn = f[2 * j];
    fn.a = &red_[j].an;
    if (q.dcn_dln != 0 && q.dcn_dr == 0) fn.value = -cn / q.dcn_dln;
    else if (q.dcn_dr != 0 && q.dcn_dln == 0) fn.equality = true, fn.value = -cn / q.dcn_dr;
    else return false;
    RowFunction& ft = f[2 * j + 1];
    ft.a = &red_[j].at;
    if (q.dct_dlt != 0 && q.dct_ds == 0) ft.value = -ct / q.dct_dlt;
    else if (q.dct_ds != 0 && q.dct_dlt == 0) ft.equality = true, ft.value = -ct / q.dct_ds;
    else return false;
  }
  ScopedSeconds timing(stats_.factor_seconds);
  // b = -F_u + A_X^T dl_X; M = K + rho A_E^T A_E.
  Vec b = -F.head(n);
  const double diag = K.diagonal().mean();
  double norm2 = 0;
  int equalities = 0;
  for (const RowFunction& r : f) {
    if (!r.equality) {
      for (const auto& [d, w] : *r.a) b[d] += w * r.value;
      continue;
    }
    ++equalities;
    for (const auto& [d, w] : *r.a) norm2 += w * w;
  }
  if (equalities == 0 || !(norm2 > 0) || !(diag > 0)) return false;
  const double rho = kRho * diag / (norm2 / equalities);
  // Every row's entries are in M's pattern whatever its set (zeros kept),
  // so the pattern, hashed at the solve's first step, holds over it.
  SpMat M = K;
  for (const RowFunction& r : f) {
    const double scale = r.equality ? rho : 0.0;
    for (const auto& [d1, w1] : *r.a) {
      b[d1] += scale * w1 * r.value;
      for (const auto& [d2, w2] : *r.a) M.coeffRef(d1, d2) += scale * w1 * w2;
    }
  }
  if (!augmented_hashed_) {
    const std::uint64_t h = pattern_hash(M);
    if (h != augmented_hash_) augmented_hash_ = h, ++augmented_version_;
    augmented_hashed_ = true;
  }
  if (!augmented_cholesky_.factorize(M, true, augmented_version_)) return false;
  std::vector<double> l(f.size(), 0.0);
  Vec du, rhs;
  for (int k = 0;; ++k) {
    rhs = b;
    for (std::size_t i = 0; i < f.size(); ++i)
      if (f[i].equality)
        for (const auto& [d, w] : *f[i].a) rhs[d] += w * l[i];
    du = augmented_cholesky_.solve(rhs);
    if (!du.allFinite()) return false;
    double worst = 0;
    const double speed = du.lpNorm<Eigen::Infinity>();
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!f[i].equality) continue;
      double ad = 0, a2 = 0;
      for (const auto& [d, w] : *f[i].a) ad += w * du[d], a2 += w * w;
      const double gap = f[i].value - ad;
      l[i] += rho * gap;
      worst = std::max(worst, std::abs(gap) / std::max(std::abs(f[i].value) + std::sqrt(a2) * speed, 1e-300));
    }
    if (worst <= kConverged) break;
    if (k + 1 == kMaxSolves) return false;
  }
  dx.resize(n + 2 * static_cast<Index>(m));
  dx.head(n) = du;
  for (std::size_t i = 0; i < f.size(); ++i) dx[n + static_cast<Index>(i)] = f[i].equality ? l[i] : f[i].value;
  ++stats_.augmented;
  return true;
}

}  // namespace rpfem
