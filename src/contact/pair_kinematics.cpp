#include "contact/pair_kinematics.hpp"

namespace rpfem {

PairKinematics die_pair(const Die& d, Index node, const std::vector<Vec2>& x, double t) {
  const DieProjection proj = d.project(x[node], t);
  PairKinematics k;
  k.k = 1;
  k.nodes[0] = node;
  k.offset = d.motion.velocity(t);
  k.n = proj.normal;
  k.gap0 = k.gap_from = proj.distance;
  return k;
}

PairKinematics segment_pair(Index node, const Edge& e, const SegmentHit& hit) {
  PairKinematics k;
  k.k = 3;
  k.nodes[0] = node, k.nodes[1] = e.a, k.nodes[2] = e.b;
  k.c[0] = 1.0, k.c[1] = -(1.0 - hit.xi), k.c[2] = -hit.xi;
  k.n = hit.normal;
  k.gap0 = k.gap_from = hit.gap;
  return k;
}

void set_gap_from(PairKinematics& k, const std::vector<Vec2>& x, const std::vector<Vec2>& x_from, double t,
                  double t_from, const Die* die) {
  Vec2 back = Vec2::Zero();
  if (die) back -= die->motion.displacement(t) - die->motion.displacement(t_from);
  for (int a = 0; a < k.k; ++a) back += k.c[a] * (x[k.nodes[a]] - x_from[k.nodes[a]]);
  k.gap_from = k.gap0 - back.dot(k.n);
}

namespace {
Vec2 relative_velocity(const PairKinematics& k, const std::vector<Vec2>& vel) {
  Vec2 u = -k.offset;
  for (int a = 0; a < k.k; ++a) u += k.c[a] * vel[k.nodes[a]];
  return u;
}
}  // namespace

double gap_rate(const PairKinematics& k, const std::vector<Vec2>& vel) { return relative_velocity(k, vel).dot(k.n); }

double slip_rate(const PairKinematics& k, const std::vector<Vec2>& vel) {
  return relative_velocity(k, vel).dot(Vec2(-k.n(1), k.n(0)));
}

}  // namespace rpfem
