#include "field_comparison.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "results.hpp"

namespace rpfem {

namespace {

struct Points {
  std::vector<Vec2> nodes, centroids;
};

Points initial_points(const std::string& h5) {
  std::vector<unsigned long long> sx, sc;
  const auto x = read_h5_dataset(h5, "/mesh/initial_coordinates", &sx);
  const auto c = read_h5_dataset(h5, "/mesh/connectivity", &sc);
  Points p;
  for (std::size_t i = 0; i < sx[0]; ++i) p.nodes.emplace_back(x[2 * i], x[2 * i + 1]);
  for (std::size_t e = 0; e < sc[0]; ++e) {
    Vec2 m = Vec2::Zero();
    for (std::size_t a = 0; a < sc[1]; ++a) m += p.nodes[static_cast<std::size_t>(c[sc[1] * e + a])];
    p.centroids.push_back(m / static_cast<double>(sc[1]));
  }
  return p;
}

Vec2 apply(PointMap map, const Vec2& p) { return map == PointMap::MirrorY ? Vec2(p(0), -p(1)) : p; }

// Index in `to` of the point at `p` (brute force: meshes of a few thousand points).
std::size_t counterpart(const Vec2& p, const std::vector<Vec2>& to, const std::string& what) {
  std::size_t best = 0;
  double d = INFINITY;
  for (std::size_t j = 0; j < to.size(); ++j)
    if (const double dj = (to[j] - p).squaredNorm(); dj < d) d = dj, best = j;
  if (!(std::sqrt(d) < 1e-9)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "no %s of the other run at (%.6g, %.6g) mm (nearest %.3g mm away)", what.c_str(),
                  p(0), p(1), std::sqrt(d));
    throw std::runtime_error(buf);
  }
  return best;
}

std::string step_group(int step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "/steps/%06d/", step);
  return buf;
}

}  // namespace

FieldDifference field_difference(const std::string& h5_a, const std::string& h5_b, int step,
                                 const std::function<bool(const Vec2&)>& select, PointMap map) {
  const Points a = initial_points(h5_a), b = initial_points(h5_b);
  const std::string g = step_group(step);
  const auto ea = read_h5_dataset(h5_a, g + "strain_rate"), eb = read_h5_dataset(h5_b, g + "strain_rate");
  const auto va = read_h5_dataset(h5_a, g + "velocity"), vb = read_h5_dataset(h5_b, g + "velocity");
  FieldDifference out;
  double de = 0, ne = 0, dv = 0, nv = 0;
  for (std::size_t e = 0; e < a.centroids.size(); ++e) {
    if (!select(a.centroids[e])) continue;
    const std::size_t f = counterpart(apply(map, a.centroids[e]), b.centroids, "element");
    de += std::pow(ea[e] - eb[f], 2), ne += ea[e] * ea[e];
    ++out.elements;
  }
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    if (!select(a.nodes[i])) continue;
    const std::size_t j = counterpart(apply(map, a.nodes[i]), b.nodes, "node");
    const Vec2 ua(va[2 * i], va[2 * i + 1]), ub = apply(map, Vec2(vb[2 * j], vb[2 * j + 1]));
    dv += (ua - ub).squaredNorm(), nv += ua.squaredNorm();
    ++out.nodes;
  }
  if (out.elements == 0 || !(ne > 0) || !(nv > 0))
    throw std::runtime_error(h5_a + ": nothing selected to compare at step " + std::to_string(step));
  out.strain_rate = std::sqrt(de / ne);
  out.velocity = std::sqrt(dv / nv);
  return out;
}

}  // namespace rpfem
