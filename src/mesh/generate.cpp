#include "mesh/generate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>

namespace rpfem {

namespace {

// A boundary curve of a block, parameter u in [0, 1].
using Curve = std::function<Vec2(double)>;

// p + u (q - p) rather than (1 - u) p + u q: a coordinate that p and q share
// (x = 0 on the axis, y = y0 on a plane) is then reproduced bitwise.
Curve line(Vec2 p, Vec2 q) {
  return [=](double u) -> Vec2 { return u == 1.0 ? q : Vec2(p + u * (q - p)); };
}

// Unit vector at angle th with the round-off of cos(pi/2) etc. removed, so
// that axis and plane points are exact.
Vec2 dir(double th) {
  double c = std::cos(th), s = std::sin(th);
  if (std::abs(c) < 1e-15) c = 0;
  if (std::abs(s) < 1e-15) s = 0;
  return {c, s};
}

Curve arc(Vec2 center, double r, double th0, double th1) {
  return [=](double u) -> Vec2 { return center + r * dir(th0 + u * (th1 - th0)); };
}

// A block mapped from the unit square (s, t) by transfinite (Coons)
// interpolation of its four boundary curves. Faces (and the side names they
// give to boundary edges, "" for none): 0 bottom t = 0, 1 right s = 1,
// 2 top t = 1, 3 left s = 0. bottom/top run in s, left/right in t, so the
// corners must agree: bottom(0) = left(0), bottom(1) = right(0), etc.
struct Block {
  int n1, n2;
  Curve bottom, right, top, left;
  std::array<std::string, 4> faces;

  Vec2 at(int i, int j) const {
    const double s = double(i) / n1, t = double(j) / n2;
    // Boundary nodes straight from the curves: arc nodes stay exactly on
    // the circle, axis nodes at x = 0.
    if (j == 0) return bottom(s);
    if (j == n2) return top(s);
    if (i == 0) return left(t);
    if (i == n1) return right(t);
    const Vec2 p00 = bottom(0), p10 = bottom(1), p01 = top(0), p11 = top(1);
    return (1 - t) * bottom(s) + t * top(s) + (1 - s) * left(t) + s * right(t) -
           ((1 - s) * (1 - t) * p00 + s * (1 - t) * p10 + (1 - s) * t * p01 + s * t * p11);
  }
};


// Meshes the blocks into one body: coincident nodes of neighbouring blocks
// are merged, boundary edges (used by exactly one element) are oriented
// with the body on their left, chained into counter-clockwise loops, and
// named after the block face they lie on.
Mesh mesh_blocks(const std::string& body, const std::vector<Block>& blocks) {
  std::vector<std::vector<Vec2>> grids;
  double h = std::numeric_limits<double>::infinity();  // smallest grid spacing
  for (const Block& b : blocks) {
    if (b.n1 < 1 || b.n2 < 1) throw InputError("mesh of '" + body + "': divisions must be >= 1");
    auto& g = grids.emplace_back();
    for (int j = 0; j <= b.n2; ++j)
      for (int i = 0; i <= b.n1; ++i) g.push_back(b.at(i, j));
    for (int j = 0; j <= b.n2; ++j)
      for (int i = 0; i <= b.n1; ++i) {
        const Vec2& p = g[j * (b.n1 + 1) + i];
        if (i < b.n1) h = std::min(h, (g[j * (b.n1 + 1) + i + 1] - p).norm());
        if (j < b.n2) h = std::min(h, (g[(j + 1) * (b.n1 + 1) + i] - p).norm());
      }
  }
  if (!(h > 0))
    throw InputError("mesh of '" + body +
                     "': zero-size element: grid points coincide in double precision; expected dimensions large "
                     "enough against the coordinates for these divisions");
  // Nodes merge within 1e-6 h (below), which must exceed the round-off of
  // their coordinates, 1e-16 of their size: a body far from the origin, or
  // far larger than its smallest element, has nodes double precision
  // cannot merge (and the merge grid's integer cells overflowed). A
  // coordinate that overflowed (a radius of 1e308: inf - inf) is not finite.
  double extent = 0;
  for (const auto& g : grids)
    for (const Vec2& p : g) extent = std::max(extent, p.allFinite() ? p.cwiseAbs().maxCoeff() : INFINITY);
  if (!(std::isfinite(extent) && extent <= 1e9 * h)) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "coordinates up to %.3g mm with elements of %.3g mm", extent, h);
    throw InputError("mesh of '" + body + "': " +
                     (std::isfinite(extent) ? std::string(buf) : "coordinates beyond double precision's range") +
                     "; expected coordinates within 1e9 times the smallest element (check the dimensions)");
  }

  Mesh m;
  m.body_names = {body};
  // Merge on a hash grid of cell = tol, checking the neighbouring cells so
  // that two copies straddling a cell border still meet.
  const double tol = 1e-6 * h;
  std::map<std::pair<long long, long long>, std::vector<Index>> cells;
  auto node = [&](const Vec2& p) {
    const long long ci = std::llround(p(0) / tol), cj = std::llround(p(1) / tol);
    for (long long di = -1; di <= 1; ++di)
      for (long long dj = -1; dj <= 1; ++dj) {
        auto it = cells.find({ci + di, cj + dj});
        if (it == cells.end()) continue;
        for (Index k : it->second)
          if ((m.x[k] - p).norm() <= tol) return k;
      }
    m.x.push_back(p);
    cells[{ci, cj}].push_back(m.num_nodes() - 1);
    return m.num_nodes() - 1;
  };

  struct Use {
    int count = 0;
    Edge edge;
    int face = -1;  // index into face_names
  };
  std::map<std::pair<Index, Index>, Use> uses;  // by sorted node pair
  std::vector<std::string> face_names;
  for (std::size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    const auto& g = grids[bi];
    std::vector<Index> ids;
    for (const Vec2& p : g) ids.push_back(node(p));
    auto id = [&](int i, int j) { return ids[j * (b.n1 + 1) + i]; };
    // A mirrored block is parametrised clockwise: reverse all its quads.
    double area = 0;
    for (int j = 0; j < b.n2; ++j)
      for (int i = 0; i < b.n1; ++i) area += cross(g[(j + 1) * (b.n1 + 1) + i + 1] - g[j * (b.n1 + 1) + i],
                                                   g[(j + 1) * (b.n1 + 1) + i] - g[j * (b.n1 + 1) + i + 1]);
    const bool flip = area < 0;
    std::array<int, 4> face_id;
    for (int f = 0; f < 4; ++f) {
      face_id[f] = -1;
      if (b.faces[f].empty()) continue;
      auto it = std::find(face_names.begin(), face_names.end(), b.faces[f]);
      face_id[f] = int(it - face_names.begin());
      if (it == face_names.end()) face_names.push_back(b.faces[f]);
    }
    for (int j = 0; j < b.n2; ++j)
      for (int i = 0; i < b.n1; ++i) {
        // Edge k of the unflipped quad runs along block face k if on it.
        std::array<Index, 4> q{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
        const std::array<bool, 4> on{j == 0, i == b.n1 - 1, j == b.n2 - 1, i == 0};
        const Index e = m.num_elements();
        for (int k = 0; k < 4; ++k) {
          Index a = q[k], c = q[(k + 1) % 4];
          if (flip) std::swap(a, c);
          Use& u = uses[{std::min(a, c), std::max(a, c)}];
          ++u.count;
          u.edge = Edge{a, c, e};
          if (on[k] && face_id[k] >= 0) u.face = face_id[k];
        }
        if (flip) std::swap(q[1], q[3]);
        m.quads.push_back(q);
      }
  }
  m.element_body.assign(m.quads.size(), 0);
  m.node_body.assign(m.x.size(), 0);

  // Chain the boundary edges into loops, each started where the face name
  // changes, so every side is a contiguous counter-clockwise run.
  std::vector<Use> bnd;
  for (const auto& [key, u] : uses)
    if (u.count == 1) bnd.push_back(u);
  std::multimap<Index, std::size_t> from;  // start node -> boundary edge
  std::map<Index, std::size_t> to;         // end node -> boundary edge
  for (std::size_t k = 0; k < bnd.size(); ++k) {
    from.emplace(bnd[k].edge.a, k);
    to[bnd[k].edge.b] = k;
  }
  std::vector<std::size_t> order;  // loop starts: face changes first
  for (std::size_t k = 0; k < bnd.size(); ++k) {
    auto prev = to.find(bnd[k].edge.a);
    if (prev == to.end() || bnd[prev->second].face != bnd[k].face) order.push_back(k);
  }
  for (std::size_t k = 0; k < bnd.size(); ++k) order.push_back(k);
  std::vector<bool> done(bnd.size(), false);
  auto& boundary = m.sides[body + ".boundary"];
  for (std::size_t start : order) {
    for (std::size_t k = start; !done[k];) {
      done[k] = true;
      boundary.push_back(bnd[k].edge);
      if (bnd[k].face >= 0) m.sides[body + "." + face_names[bnd[k].face]].push_back(bnd[k].edge);
      auto [lo, hi] = from.equal_range(bnd[k].edge.b);
      for (auto it = lo; it != hi; ++it)
        if (!done[it->second]) k = it->second;
    }
  }
  return m;
}

void check_positive(const std::string& body, const char* what, double v) {
  if (!(v > 0)) throw InputError("mesh of '" + body + "': " + what + " must be > 0");
}

}  // namespace

Mesh make_rectangle(const std::string& body, const RectangleSpec& s) {
  check_positive(body, "width", s.width);
  check_positive(body, "height", s.height);
  const Vec2 p0(s.x0, s.y0), p1(s.x0 + s.width, s.y0), p2(s.x0 + s.width, s.y0 + s.height),
      p3(s.x0, s.y0 + s.height);
  return mesh_blocks(body, {{s.nx, s.ny, line(p0, p1), line(p1, p2), line(p3, p2), line(p0, p3),
                             {"bottom", "right", "top", "left"}}});
}

Mesh make_quadrilateral(const std::string& body, const QuadrilateralSpec& s) {
  const auto& c = s.corners;
  for (int i = 0; i < 4; ++i)
    if (!(cross(c[(i + 1) % 4] - c[i], c[(i + 2) % 4] - c[(i + 1) % 4]) > 0)) {
      const int k = (i + 1) % 4;
      throw InputError("mesh of '" + body + "': corner " + std::to_string(k + 1) + " (" + std::to_string(c[k](0)) +
                       ", " + std::to_string(c[k](1)) +
                       ") turns clockwise or not at all; expected a convex quadrilateral, counter-clockwise from "
                       "the bottom-left corner");
    }
  return mesh_blocks(body, {{s.nx, s.ny, line(c[0], c[1]), line(c[1], c[2]), line(c[3], c[2]), line(c[0], c[3]),
                             {"bottom", "right", "top", "left"}}});
}

Mesh make_ring(const std::string& body, const RingSpec& s) {
  if (!(s.inner_radius >= 0)) throw InputError("mesh of '" + body + "': inner_radius must be >= 0");
  check_positive(body, "outer_radius - inner_radius", s.outer_radius - s.inner_radius);
  check_positive(body, "height", s.height);
  const double r0 = s.inner_radius, r1 = s.outer_radius, y1 = s.y0 + s.height;
  const Vec2 p0(r0, s.y0), p1(r1, s.y0), p2(r1, y1), p3(r0, y1);
  return mesh_blocks(body, {{s.nr, s.ny, line(p0, p1), line(p1, p2), line(p3, p2), line(p0, p3),
                             {"bottom", "outer", "top", "inner"}}});
}

Mesh make_disk(const std::string& body, const DiskSpec& s) {
  check_positive(body, "radius", s.radius);
  const double R = s.radius;
  // Inner quadrilateral O A C D: A and D at a on the plane and the axis, C
  // on the diagonal. With C at 0.79 a the three elements meeting at C all
  // have about 120 degree corners there (a true square, C = a, would leave 135
  // degrees to the outer blocks; C on the chord A-D, 180 to the inner one).
  const double a = 0.5 * R, c = 0.79 * a;
  std::vector<Block> blocks;
  auto add_quarter = [&](double sy) {  // sy = +1 upper, -1 lower (mirrored)
    auto P = [&](double x, double y) { return Vec2(x, s.center_y + sy * y); };
    const Vec2 O = P(0, 0), A = P(a, 0), C = P(c, c), D = P(0, a), E = P(R, 0), F = P(0, R);
    const Vec2 M = P(0, 0) + R * dir(sy * kPi / 4);
    const Curve arc1 = arc(O, R, 0, sy * kPi / 4), arc2 = arc(O, R, sy * kPi / 4, sy * kPi / 2);
    blocks.push_back({s.n, s.n, line(O, A), line(A, C), line(D, C), line(O, D), {"plane", "", "", "axis"}});
    blocks.push_back({s.layers, s.n, line(A, E), arc1, line(C, M), line(A, C), {"plane", "arc", "", ""}});
    blocks.push_back({s.layers, s.n, line(C, M), arc2, line(D, F), line(C, D), {"", "arc", "axis", ""}});
  };
  if (s.part == DiskPart::Half) {
    add_quarter(1.0);
    add_quarter(-1.0);
  } else {
    add_quarter(s.part == DiskPart::UpperQuarter ? 1.0 : -1.0);
  }
  return mesh_blocks(body, blocks);
}

}  // namespace rpfem
