#include "model/die_interference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/polygon.hpp"

namespace rpfem {

DieInterference die_interference(const Scene& scene, const std::vector<Vec2>& x, double t) {
  DieInterference worst;
  for (const ContactPair& pair : scene.contact_pairs) {
    if (!pair.with_die()) continue;
    const Die& die = scene.dies[pair.die_id];
    const auto& outline = scene.mesh.sides.at(scene.mesh.body_names[pair.body_id] + ".boundary");
    for (const Vec2& p : die.profile.corner_points(die.motion.displacement(t), true)) {
      // Inside the outline by the crossing rule; the nearest edge by distance.
      bool inside = false;
      double nearest = std::numeric_limits<double>::infinity();
      for (const Edge& e : outline) {
        const Vec2& a = x[e.a];
        const Vec2& b = x[e.b];
        if ((a(1) > p(1)) != (b(1) > p(1)) && p(0) < a(0) + (p(1) - a(1)) * (b(0) - a(0)) / (b(1) - a(1)))
          inside = !inside;
        nearest = std::min(nearest, segment_distance(p, a, b));
      }
      const double size = scene.remesh.size.at(pair.body_id) * scene.remesh.die_corner_size;
      if (inside && nearest / size > worst.relative) worst = {nearest, nearest / size, pair.die_id, pair.body_id};
    }
  }
  return worst;
}

}  // namespace rpfem
