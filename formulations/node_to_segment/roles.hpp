// Slave and master between two deformable bodies, Hallquist's rule (Hallquist,
// Goudreau, Benson 1985; paper sec. 2): the body whose nodes penetrate the
// other's boundary is the slave. One-pass contact holds only the slave's
// nodes out of the master, so when the master's nodes penetrate the slave
// more than the other way round the roles switch. At the start, with no
// penetration either way, the finer surface (shorter mean edge) is the slave.
#pragma once
#include <vector>

#include "contact/segment_search.hpp"

namespace rpfem {

struct Penetrations {
  int count = 0;       // nodes deeper than the tolerance
  double deepest = 0;  // mm, over all nodes inside
};

// From the search hits of one surface's nodes on the other (find_segments):
// the nodes inside it by more than tol (mm), and the deepest.
Penetrations count_penetrations(const std::vector<std::optional<SegmentHit>>& hits, double tol);

// The slave side (0 or 1) after this configuration: `current` unless the
// master's nodes penetrate the slave at more nodes than the slave's nodes
// penetrate the master, and deeper than `guard` (mm). The caller passes the
// depth that made the last switch: roles switch back only if the master
// now penetrates deeper than that, i.e. the switch made things worse (one
// pass lets either side's master sink a little every step; without the
// guard a flat interface switched at every step and back).
int hallquist_slave(int current, const Penetrations& from0, const Penetrations& from1, double guard = 0);

}  // namespace rpfem
