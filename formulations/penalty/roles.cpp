#include "penalty/roles.hpp"

#include <algorithm>

namespace rpfem {

Penetrations count_penetrations(const std::vector<std::optional<SegmentHit>>& hits, double tol) {
  Penetrations p;
  for (const auto& hit : hits) {
    if (hit && hit->gap < 0) p.deepest = std::max(p.deepest, -hit->gap);
    if (hit && hit->gap < -tol) ++p.count;
  }
  return p;
}

double mean_edge_length(const std::vector<Vec2>& x, const ContactSurface& s) {
  double sum = 0;
  for (const Edge& e : s.edges) sum += (x[e.b] - x[e.a]).norm();
  return s.edges.empty() ? 0.0 : sum / s.edges.size();
}

int hallquist_slave(int current, const Penetrations& from0, const Penetrations& from1, double guard) {
  const Penetrations& slave = current == 0 ? from0 : from1;
  const Penetrations& master = current == 0 ? from1 : from0;
  return master.count > slave.count && master.deepest > guard ? 1 - current : current;
}

}  // namespace rpfem
