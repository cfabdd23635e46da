#include "node_to_segment/roles.hpp"

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

int hallquist_slave(int current, const Penetrations& from0, const Penetrations& from1, double guard) {
  const Penetrations& slave = current == 0 ? from0 : from1;
  const Penetrations& master = current == 0 ? from1 : from0;
  return master.count > slave.count && master.deepest > guard ? 1 - current : current;
}

}  // namespace rpfem
