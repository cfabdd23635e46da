#include "mesh/outline_simplify.hpp"

#include <cmath>
#include <functional>
#include <queue>
#include <tuple>

#include "mesh/polygon.hpp"

namespace rpfem {

namespace {

// The volume node i adds between its neighbours p and q (positive where
// the outline bulges out at i).
double triangle_volume(const Vec2& p, const Vec2& i, const Vec2& q, Geometry g) {
  return edge_volume(p, i, g).v + edge_volume(i, q, g).v + edge_volume(q, p, g).v;
}

}  // namespace

std::vector<std::size_t> simplify_outline(const std::vector<Vec2>& x, const std::vector<bool>& fixed,
                                          const OutlineSimplification& how) {
  const std::size_t n = x.size();
  double volume = 0;
  for (std::size_t k = 0; k < n; ++k) volume += edge_volume(x[k], x[(k + 1) % n], how.geometry).v;
  double budget = how.volume_tolerance * std::abs(volume);
  // A doubly linked ring over the nodes still in.
  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t k = 0; k < n; ++k) prev[k] = (k + n - 1) % n, next[k] = (k + 1) % n;
  std::vector<bool> in(n, true);
  std::vector<unsigned> version(n, 0);  // bumped when a neighbour goes: older queue entries are stale
  // Candidates by the length of the edge that would replace their two,
  // shortest first (ties: lowest index, so the result does not depend on
  // the queue's internals).
  using Entry = std::tuple<double, std::size_t, unsigned>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  const auto offer = [&](std::size_t k) {
    if (fixed[k]) return;
    const double L = (x[next[k]] - x[prev[k]]).norm();
    if (L <= how.max_length.at(k)) queue.emplace(L, k, version[k]);
  };
  for (std::size_t k = 0; k < n; ++k) offer(k);
  std::size_t left = n;
  while (left > 3 && !queue.empty()) {
    const auto [L, k, v] = queue.top();
    queue.pop();
    if (!in[k] || v != version[k]) continue;
    const double dv = std::abs(triangle_volume(x[prev[k]], x[k], x[next[k]], how.geometry));
    if (dv > budget) continue;  // the budget only shrinks: k stays unless a neighbour goes
    budget -= dv;
    in[k] = false;
    --left;
    const std::size_t p = prev[k], q = next[k];
    next[p] = q, prev[q] = p;
    ++version[p], ++version[q];
    offer(p), offer(q);
  }
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < n; ++k)
    if (in[k]) kept.push_back(k);
  return kept;
}

}  // namespace rpfem
