#include "mesh/generate.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

namespace rpfem {

namespace {

using BlockMap = std::function<Vec2(double s, double t)>;

// Faces of a block: 0 t = 0, 1 s = 1, 2 t = 1, 3 s = 0; "" = internal.
struct Block {
  int n1, n2;
  BlockMap map;
  std::array<std::string, 4> faces;
};

Mesh mesh_blocks(const std::string& body, const std::vector<Block>& blocks, double size) {
  Mesh m;
  m.body_names = {body};
  const double tol = 1e-9 * size;
  std::map<std::pair<long long, long long>, Index> index;  // merge on a fine grid
  auto node = [&](const Vec2& p) {
    const auto key = std::make_pair(std::llround(p(0) / tol / 10), std::llround(p(1) / tol / 10));
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const Index id = m.num_nodes();
    m.x.push_back(p);
    index.emplace(key, id);
    return id;
  };
  // Face of each block-boundary edge, keyed by its sorted node pair.
  std::map<std::pair<Index, Index>, std::string> face_of;
  std::map<std::pair<Index, Index>, std::pair<int, Edge>> uses;
  for (const Block& b : blocks) {
    std::vector<Index> ids((b.n1 + 1) * (b.n2 + 1));
    for (int j = 0; j <= b.n2; ++j)
      for (int i = 0; i <= b.n1; ++i) ids[j * (b.n1 + 1) + i] = node(b.map(double(i) / b.n1, double(j) / b.n2));
    auto at = [&](int i, int j) { return ids[j * (b.n1 + 1) + i]; };
    for (int j = 0; j < b.n2; ++j)
      for (int i = 0; i < b.n1; ++i) {
        std::array<Index, 4> q{at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
        const Vec2 d1 = m.x[q[2]] - m.x[q[0]], d2 = m.x[q[3]] - m.x[q[1]];
        if (d1(0) * d2(1) - d1(1) * d2(0) < 0) std::swap(q[1], q[3]);  // keep counter-clockwise
        const Index e = m.num_elements();
        m.quads.push_back(q);
        for (int k = 0; k < 4; ++k) {
          const Index a = q[k], c = q[(k + 1) % 4];
          auto& u = uses[{std::min(a, c), std::max(a, c)}];
          ++u.first;
          u.second = Edge{a, c, e};
        }
        // Block faces touched by this element.
        auto mark = [&](Index a, Index c, const std::string& f) {
          if (!f.empty()) face_of[{std::min(a, c), std::max(a, c)}] = f;
        };
        if (j == 0) mark(at(i, 0), at(i + 1, 0), b.faces[0]);
        if (i == b.n1 - 1) mark(at(b.n1, j), at(b.n1, j + 1), b.faces[1]);
        if (j == b.n2 - 1) mark(at(i, b.n2), at(i + 1, b.n2), b.faces[2]);
        if (i == 0) mark(at(0, j), at(0, j + 1), b.faces[3]);
      }
  }
  m.element_body.assign(m.quads.size(), 0);
  m.node_body.assign(m.x.size(), 0);
  auto& boundary = m.sides[body + ".boundary"];
  for (const auto& [key, u] : uses) {
    if (u.first != 1) continue;
    boundary.push_back(u.second);
    auto f = face_of.find(key);
    if (f != face_of.end()) m.sides[body + "." + f->second].push_back(u.second);
  }
  return m;
}

}  // namespace

Mesh make_rectangle(const std::string& body, const RectangleSpec& s) {
  Block b{s.nx, s.ny, [&](double u, double v) { return Vec2(s.x0 + u * s.width, s.y0 + v * s.height); },
          {"bottom", "right", "top", "left"}};
  return mesh_blocks(body, {b}, std::max(s.width, s.height));
}

Mesh make_ring(const std::string& body, const RingSpec& s) {
  const double w = s.outer_radius - s.inner_radius;
  Block b{s.nr, s.ny, [&](double u, double v) { return Vec2(s.inner_radius + u * w, s.y0 + v * s.height); },
          {"bottom", "outer", "top", "inner"}};
  return mesh_blocks(body, {b}, std::max(s.outer_radius, s.height));
}

Mesh make_disk(const std::string& body, const DiskSpec& s) {
  const double R = s.radius;
  const double a = 0.5 * R, c = 0.42 * R;  // inner quadrilateral (0,0) (a,0) (c,c) (0,a)
  const double sign = s.part == DiskPart::LowerQuarter ? -1.0 : 1.0;
  std::vector<Block> blocks;
  auto add_quarter = [&](double sy) {
    auto P = [sy, &s](double x, double y) { return Vec2(x, s.center_y + sy * y); };
    const std::string plane = "plane";
    blocks.push_back({s.n, s.n,
                      [=](double u, double v) {
                        const Vec2 p = (1 - u) * (1 - v) * Vec2(0, 0) + u * (1 - v) * Vec2(a, 0) +
                                       u * v * Vec2(c, c) + (1 - u) * v * Vec2(0, a);
                        return P(p(0), p(1));
                      },
                      {plane, "", "", "axis"}});
    blocks.push_back({s.layers, s.n,
                      [=](double u, double v) {
                        const Vec2 in = Vec2(a, 0) + v * (Vec2(c, c) - Vec2(a, 0));
                        const double th = v * kPi / 4;
                        const Vec2 p = (1 - u) * in + u * R * Vec2(std::cos(th), std::sin(th));
                        return P(p(0), p(1));
                      },
                      {plane, "arc", "", ""}});
    blocks.push_back({s.layers, s.n,
                      [=](double u, double v) {
                        const Vec2 in = Vec2(c, c) + v * (Vec2(0, a) - Vec2(c, c));
                        const double th = kPi / 4 + v * kPi / 4;
                        // Exactly on the axis at v = 1 and on the circle at u = 1.
                        Vec2 out = R * Vec2(std::cos(th), std::sin(th));
                        if (v == 1.0) out = Vec2(0, R);
                        const Vec2 p = (1 - u) * in + u * out;
                        return P(p(0), p(1));
                      },
                      {"", "arc", "axis", ""}});
  };
  if (s.part == DiskPart::Half) {
    add_quarter(1.0);
    add_quarter(-1.0);
  } else {
    add_quarter(sign);
  }
  return mesh_blocks(body, blocks, R);
}

}  // namespace rpfem
