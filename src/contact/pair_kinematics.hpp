// A slave point against its master, as every contact formulation sees it
// (paper eq. 5, 9, 12), shared by the formulations (the kernel does not use
// it): the relative velocity as weights c_a on the velocities of the row's
// nodes (the slave node first; each node once):
//   u = sum_a c_a v_a - offset
// A node against a segment of another body (3 nodes) or a rigid die (1
// node, offset the die's velocity):
//   u = v_s - (1 - xi) v_a - xi v_b      (body master at xi)
//   u = v_s - v_die                      (die master)
// A mortar row (formulations/mortar): the slave node j and its neighbours,
// c = D_jk / W_j, against the master nodes its shape function's support
// faces, c = -M_jL / W_j.
//   gamma_N = u . n   (gap rate; paper eq. 5 with the opposite sign: > 0 opens)
//   gamma_T = u . t,  t = (-n_y, n_x)
// and the gap at the end of a step of length dt, linearized in the
// velocities (the geometry is fixed within the step):
//   g_end = g_from + dt gamma_N
// with g_from the gap where the velocity moves the nodes from.
#pragma once
#include <array>
#include <vector>

#include "contact/segment_search.hpp"
#include "core/types.hpp"
#include "geometry/die.hpp"

namespace rpfem {

// The most nodes a row couples (a mortar row on a master surface four times
// finer than its slave's).
constexpr int kMaxRowNodes = 12;

struct PairKinematics {
  int k = 1;                                  // nodes: the slave first
  std::array<Index, kMaxRowNodes> nodes{};    // mesh node ids
  std::array<double, kMaxRowNodes> c{1};      // u = sum_a c_a v_a - offset
  Vec2 offset = Vec2::Zero();       // die velocity (die master), mm/s
  Vec2 n = Vec2::Zero();            // unit master outward normal
  double gap0 = 0;                  // mm, in the configuration solved on
  double gap_from = 0;              // mm, where the velocity moves the nodes from

  // Adds weight w to node `node` (a new node at the end); false when the
  // row is full.
  bool add(Index node, double w) {
    for (int a = 0; a < k; ++a)
      if (nodes[a] == node) return c[a] += w, true;
    if (k == kMaxRowNodes) return false;
    nodes[k] = node, c[k] = w, ++k;
    return true;
  }
};

// Node `node` at x[node] against die d at time t.
PairKinematics die_pair(const Die& d, Index node, const std::vector<Vec2>& x, double t);
// Node `node` against master edge e at the search hit.
PairKinematics segment_pair(Index node, const Edge& e, const SegmentHit& hit);

// The gap where the velocity moves the nodes from: the configuration x_from
// at time t_from instead of x at t (the midpoint scheme's half-step solve):
// the same master point moved back by the relative displacement in between.
// `die` is the master die, or nullptr for a body master.
void set_gap_from(PairKinematics& k, const std::vector<Vec2>& x, const std::vector<Vec2>& x_from, double t,
                  double t_from, const Die* die);

// gamma_N and gamma_T at nodal velocities vel (mm/s).
double gap_rate(const PairKinematics& k, const std::vector<Vec2>& vel);
double slip_rate(const PairKinematics& k, const std::vector<Vec2>& vel);

}  // namespace rpfem
