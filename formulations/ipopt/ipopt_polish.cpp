// The polish of an exact-friction solution (ipopt_step_solver.hpp,
// polish()): Newton on the program's Kuhn-Tucker conditions with a guess of
// its sets as equalities.
#include "ipopt/ipopt_step_solver.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "model/step_problem.hpp"

namespace rpfem {

namespace {

// Newton iterations of a polish (from Ipopt's solution: one or two reach
// round-off), and the constraint residual (over v_ref) and set violations
// (over the bound, the force scale or v_ref) it may leave.
constexpr int kPolishIterations = 4;
// Guesses of the sets a polish tries (polish): the backward extrusion's
// took up to six, its first guess wrong on 15 to 21 rows slipping slower
// than about 1e-4 of the punch speed (an interior point's slip below
// sqrt(mu v_ref / g) reads as sticking).
constexpr int kPolishRounds = 8;
constexpr double kPolishRoundOff = 1e-12;

}  // namespace

bool IpoptStepSolver::polish(StepProblem& problem, NlpOutcome& out) {
  // The program's Kuhn-Tucker conditions with a guess of its sets as
  // equalities, in u and the forces of the rows held (N on a row in
  // contact, A; T on a sticking row, S; a slipping row's T = -g sigma is
  // known, sigma = sign gamma_T):
  //   F_u = R(u) - sum_A N_j a_N,j - sum_S T_k a_T,k + sum_slip g_k sigma_k a_T,k = 0
  //   a_N,j . u - l_j = 0 (j in A),   a_T,k . u + t_0,k = 0 (k in S)
  // Newton from Ipopt's solution: [K -C^T; C 0] (du, dforce) = -(F_u, F_c),
  // C the rows held, K the consistent tangent. The first guess: each row
  // on the side of the larger of its two complementary quantities in
  // their scales (in contact where N / F_s > (a_N . u - l) / v_ref,
  // sticking where |gamma_T| / v_ref < 1 - |T| / g, as
  // IpoptEnforcement::classify). A row the result puts outside its
  // inequalities changes its set (tensile: open; penetrating: in contact;
  // beyond its bound: slipping against its force; slipping against its
  // force: sticking), as a primal-dual active set step (Hintermueller, Ito
  // and Kunisch 2002, SIAM J. Optim. 13, sec. 2), for kPolishRounds guesses.
  // A node in contact with two dies has its velocity fixed by their
  // normals: where it sticks, the split of its reaction between them is
  // not determined (the rows held would be dependent), and its friction
  // force is taken as zero (a valid sticking force), as ssn's rule
  // (docs/theory.md, "A node on two dies"); where it slips along a die,
  // the force is that die's bound.
  const Index n = out.u.size();
  const std::size_t normal = row_of_.size(), nf = friction_of_.size();
  const auto dot = [n](const LinearRow& r, const Vec& u) {
    double s = 0;
    for (const auto& [d, a] : r.terms)
      if (d < n) s += a * u[d];
    return s;
  };
  // gamma_T of friction k: its second row is s + gamma_T >= 0, gamma_T =
  // a_T . u + t_0 with t_0 = -lower.
  const auto slip_row = [&](std::size_t k) -> const LinearRow& { return nlp_rows_[normal + 2 * k + 1]; };
  const auto gamma = [&](std::size_t k, const Vec& u) { return dot(slip_row(k), u) - slip_row(k).lower; };
  // The slave node of a row against a die (a row of one node), else -1.
  const auto die_node = [&](int row) -> Index {
    const PairKinematics& k = *(*rows_)[row].kin;
    return k.k == 1 ? k.nodes[0] : -1;
  };
  std::vector<char> active(normal);
  std::vector<double> N(normal), T(nf), sigma(nf, 0.0);  // sigma: 0 sticking
  for (std::size_t j = 0; j < normal; ++j) {
    N[j] = -out.lambda[j];
    active[j] = N[j] / force_scale_ > (dot(nlp_rows_[j], out.u) - nlp_rows_[j].lower) / speed_scale_;
  }
  for (std::size_t k = 0; k < nf; ++k) {
    const double gk = gamma(k, out.u), g = nlp_cost_[k];
    T[k] = out.lambda[normal + 2 * k] - out.lambda[normal + 2 * k + 1];
    if (!(std::abs(gk) / speed_scale_ < 1 - std::abs(T[k]) / g))
      sigma[k] = gk > 0 ? 1.0 : gk < 0 ? -1.0 : T[k] < 0 ? 1.0 : -1.0;
  }
  Vec u, R, F;
  double scale = 0;
  for (int round = 0; round < kPolishRounds; ++round) {
    // The rows held: (row, constant, whose force: normal j or friction k).
    struct Held {
      const LinearRow* row;
      double constant;
      std::size_t index;
      bool friction;
    };
    std::vector<Held> held;
    std::map<Index, int> on_dies;  // slave node: its rows in contact against dies
    for (std::size_t j = 0; j < normal; ++j)
      if (active[j]) {
        held.push_back({&nlp_rows_[j], -nlp_rows_[j].lower, j, false});
        if (die_node(row_of_[j]) >= 0) ++on_dies[die_node(row_of_[j])];
      }
    // Sticking rows of a node on two dies: T = 0, not held.
    std::vector<char> pinned(nf, 0);
    for (std::size_t k = 0; k < nf; ++k) {
      const Index node = die_node(friction_of_[k]);
      pinned[k] = sigma[k] == 0 && node >= 0 && on_dies[node] > 1;
      if (pinned[k]) T[k] = 0;
      else if (sigma[k] == 0) held.push_back({&slip_row(k), -slip_row(k).lower, k, true});
    }
    const Index m = static_cast<Index>(held.size());
    const auto force = [&](const Held& h) -> double& { return h.friction ? T[h.index] : N[h.index]; };
    if (round == 0) u = out.u;  // then from the last guess's solution
    const auto residual = [&] {
      problem.residual(u, R, scale);
      F.resize(n + m);
      F.head(n) = R;
      for (std::size_t k = 0; k < nf; ++k)
        if (sigma[k] != 0)
          for (const auto& [d, a] : slip_row(k).terms)
            if (d < n) F[d] += nlp_cost_[k] * sigma[k] * a;
      for (Index i = 0; i < m; ++i) {
        const Held& h = held[i];
        F[n + i] = dot(*h.row, u) + h.constant;
        for (const auto& [d, a] : h.row->terms)
          if (d < n) F[d] -= force(h) * a;
      }
    };
    residual();
    for (int it = 0; it < kPolishIterations; ++it) {
      const SpMat& K = problem.tangent(u, true);
      std::vector<Eigen::Triplet<double, int>> trip;
      trip.reserve(K.nonZeros() + 4 * held.size() * kMaxRowNodes);
      for (Eigen::Index c = 0; c < K.outerSize(); ++c)
        for (SpMat::InnerIterator e(K, c); e; ++e) trip.emplace_back(e.row(), e.col(), e.value());
      for (Index i = 0; i < m; ++i)
        for (const auto& [d, a] : held[i].row->terms)
          if (d < n) trip.emplace_back(d, n + i, -a), trip.emplace_back(n + i, d, a);
      SpMat J(n + m, n + m);
      J.setFromTriplets(trip.begin(), trip.end());
      if (!polish_lu_.factorize(J, false, ++polish_pattern_)) return false;  // the rows held are dependent
      const Vec dx = polish_lu_.solve(-F);
      if (!dx.allFinite()) return false;
      u += dx.head(n);
      for (Index i = 0; i < m; ++i) force(held[i]) += dx[n + i];
      residual();
      if (dx.head(n).norm() <= kPolishRoundOff * u.norm()) break;
    }
    // As stationary as Ipopt's solution (its measured stationarity, its tol
    // or the round-off floor), the rows held met.
    if (F.head(n).norm() / scale > std::max({kkt_.stationarity, tol_, kRoundOffMultiple * kkt_.round_off})) return false;
    for (Index i = 0; i < m; ++i)
      if (std::abs(F[n + i]) > kPolishRoundOff * speed_scale_) return false;
    // The inequalities: rows outside them change their set.
    int changed = 0;
    for (std::size_t j = 0; j < normal; ++j) {
      const double rate = dot(nlp_rows_[j], u) - nlp_rows_[j].lower;
      if (active[j] && N[j] < -kPolishRoundOff * force_scale_) active[j] = 0, N[j] = 0, ++changed;  // tensile
      else if (!active[j] && rate < -kPolishRoundOff * speed_scale_) active[j] = 1, ++changed;    // penetrating
    }
    for (std::size_t k = 0; k < nf; ++k) {
      const double g = nlp_cost_[k], gk = gamma(k, u);
      if (pinned[k] && std::abs(gk) > kPolishRoundOff * speed_scale_) {
        sigma[k] = gk > 0 ? 1.0 : -1.0, ++changed;  // slipping along a die
      } else if (sigma[k] == 0 && std::abs(T[k]) > g * (1 + kPolishRoundOff)) {
        sigma[k] = T[k] < 0 ? 1.0 : -1.0, ++changed;  // beyond its bound: slipping against its force
      } else if (sigma[k] != 0 && sigma[k] * gk < -kPolishRoundOff * speed_scale_) {
        T[k] = -g * sigma[k], sigma[k] = 0, ++changed;  // slipping against its force: sticking, from its force
      }
    }
    if (changed) continue;
    // Ipopt's multipliers of the polished solution: -N on the rows in
    // contact; a sticking row's p = (g - T) / 2, q = (g + T) / 2; a
    // slipping row's g on its active side.
    std::vector<double> lambda(out.lambda.size(), 0.0);
    Vec slack = Vec::Zero(static_cast<Index>(nf));
    for (std::size_t j = 0; j < normal; ++j)
      if (active[j]) lambda[j] = -N[j];
    for (std::size_t k = 0; k < nf; ++k) {
      const double g = nlp_cost_[k];
      if (sigma[k] == 0) {
        lambda[normal + 2 * k] = -0.5 * (g - T[k]);
        lambda[normal + 2 * k + 1] = -0.5 * (g + T[k]);
      } else {
        lambda[normal + 2 * k + (sigma[k] > 0 ? 0 : 1)] = -g;
        slack[static_cast<Index>(k)] = std::abs(gamma(k, u));
      }
    }
    out.u = u;
    out.slack = slack;
    out.lambda = std::move(lambda);
    out.grad = R;
    out.grad_scale = scale;
    return true;
  }
  return false;
}

}  // namespace rpfem
