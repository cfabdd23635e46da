#include "mesh/field_transfer.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "fem/quad4.hpp"

namespace rpfem {

namespace {

Vec2 map_point(const Quad4Coords& X, double xi, double eta) {
  const Eigen::Vector4d N = quad4_shape(xi, eta);
  return N(0) * X[0] + N(1) * X[1] + N(2) * X[2] + N(3) * X[3];
}

Quad4Coords corners(const Mesh& m, const std::vector<Vec2>& x, Index e) {
  return {x[m.quads[e][0]], x[m.quads[e][1]], x[m.quads[e][2]], x[m.quads[e][3]]};
}

// The parameters of p in the element (Newton on the bilinear map); the
// returned point may lie outside [-1, 1]^2.
Vec2 parameters_of(const Quad4Coords& X, const Vec2& p) {
  Vec2 s = Vec2::Zero();
  for (int it = 0; it < 30; ++it) {
    const double xi = s(0), eta = s(1);
    Eigen::Matrix2d J;  // columns d x / d xi, d x / d eta
    J.col(0) = 0.25 * (-(1 - eta) * X[0] + (1 - eta) * X[1] + (1 + eta) * X[2] - (1 + eta) * X[3]);
    J.col(1) = 0.25 * (-(1 - xi) * X[0] - (1 + xi) * X[1] + (1 + xi) * X[2] + (1 - xi) * X[3]);
    const Vec2 step = J.partialPivLu().solve(map_point(X, xi, eta) - p);
    s -= step;
    if (!(s.allFinite()) || step.norm() < 1e-14) break;
  }
  return s;
}

// Old elements by the grid cells their bounding boxes touch.
class ElementGrid {
 public:
  ElementGrid(const Mesh& m, const std::vector<Vec2>& x) {
    lo_ = hi_ = x[m.quads.at(0)[0]];
    double edges = 0;
    for (const auto& q : m.quads)
      for (int i = 0; i < 4; ++i) {
        lo_ = lo_.cwiseMin(x[q[i]]), hi_ = hi_.cwiseMax(x[q[i]]);
        edges += (x[q[(i + 1) % 4]] - x[q[i]]).norm();
      }
    cell_ = std::max(edges / (4.0 * m.quads.size()), 1e-12);
    nx_ = 1 + static_cast<int>((hi_(0) - lo_(0)) / cell_);
    ny_ = 1 + static_cast<int>((hi_(1) - lo_(1)) / cell_);
    cells_.resize(static_cast<std::size_t>(nx_) * ny_);
    for (Index e = 0; e < m.num_elements(); ++e) {
      Vec2 a = x[m.quads[e][0]], b = a;
      for (int i = 1; i < 4; ++i) a = a.cwiseMin(x[m.quads[e][i]]), b = b.cwiseMax(x[m.quads[e][i]]);
      const auto [i0, j0] = cell(a);
      const auto [i1, j1] = cell(b);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(e);
    }
  }
  // Elements whose boxes touch p's cell; empty outside the grid.
  const std::vector<Index>& at(const Vec2& p) const {
    static const std::vector<Index> none;
    if ((p.array() < lo_.array()).any() || (p.array() > hi_.array()).any()) return none;
    const auto [i, j] = cell(p);
    return cells_[static_cast<std::size_t>(j) * nx_ + i];
  }

 private:
  std::pair<int, int> cell(const Vec2& p) const {
    return {std::clamp(static_cast<int>((p(0) - lo_(0)) / cell_), 0, nx_ - 1),
            std::clamp(static_cast<int>((p(1) - lo_(1)) / cell_), 0, ny_ - 1)};
  }
  Vec2 lo_, hi_;
  double cell_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<Index>> cells_;
};

}  // namespace

std::vector<double> recover_at_nodes(const Mesh& m, const std::vector<Vec2>& x, const std::vector<GaussValues>& g) {
  std::vector<std::vector<Index>> around(x.size());
  for (Index e = 0; e < m.num_elements(); ++e)
    for (Index n : m.quads[e]) around[n].push_back(e);
  std::vector<double> out(x.size(), 0.0);
  for (std::size_t n = 0; n < x.size(); ++n) {
    if (around[n].empty()) continue;
    // The plane a + b dx + c dy through the patch's points, dx = x - x_n
    // scaled by the patch's size: a is the value at the node.
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    double scale = 0, mean = 0;
    int points = 0;
    for (Index e : around[n]) {
      const auto X = corners(m, x, e);
      for (const Vec2& c : X) scale = std::max(scale, (c - x[n]).norm());
    }
    for (Index e : around[n]) {
      const auto X = corners(m, x, e);
      for (int q = 0; q < 4; ++q) {
        const Vec2 d = (map_point(X, kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]) - x[n]) / scale;
        const Eigen::Vector3d row(1, d(0), d(1));
        A += row * row.transpose();
        rhs += row * g[e][q];
        mean += g[e][q], ++points;
      }
    }
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
    // Every patch has at least one element's four points, which span a
    // plane; a degenerate element's patch takes the mean.
    out[n] = lu.rank() == 3 ? lu.solve(rhs)(0) : mean / points;
  }
  return out;
}

namespace {

// Where point p lies in the old mesh: the element containing it and its
// parameters there, else the element whose parameter square comes nearest
// (parameters clamped to it).
std::pair<Index, Vec2> locate(const Mesh& m, const std::vector<Vec2>& x, const ElementGrid& grid, const Vec2& p) {
  Index best = -1;
  Vec2 best_s = Vec2::Zero();
  double best_miss = std::numeric_limits<double>::infinity();
  const auto consider = [&](Index o) {
    const auto Y = corners(m, x, o);
    const Vec2 s = parameters_of(Y, p);
    if (!s.allFinite()) return;
    const Vec2 clamped = s.cwiseMax(-1.0).cwiseMin(1.0);
    const bool inside = (s - clamped).cwiseAbs().maxCoeff() <= 1e-9;
    const double miss = inside ? 0.0 : (map_point(Y, clamped(0), clamped(1)) - p).norm();
    if (miss < best_miss) best = o, best_s = clamped, best_miss = miss;
  };
  for (Index o : grid.at(p)) consider(o);
  if (best < 0 || best_miss > 0)
    for (Index o = 0; o < m.num_elements() && best_miss > 0; ++o) consider(o);
  return {best, best_s};
}

// Nodal values interpolated at p.
template <class T>
T interpolate(const Mesh& m, const std::vector<T>& nodal, const std::pair<Index, Vec2>& at) {
  const Eigen::Vector4d N = quad4_shape(at.second(0), at.second(1));
  T v = N(0) * nodal[m.quads[at.first][0]];
  for (int i = 1; i < 4; ++i) v += N(i) * nodal[m.quads[at.first][i]];
  return v;
}

}  // namespace

std::vector<GaussValues> transfer_gauss_field(const Mesh& old_mesh, const std::vector<Vec2>& old_x,
                                              const std::vector<GaussValues>& g, const Mesh& new_mesh,
                                              const std::vector<Vec2>& new_x) {
  const std::vector<double> nodal = recover_at_nodes(old_mesh, old_x, g);
  const ElementGrid grid(old_mesh, old_x);
  std::vector<GaussValues> out(new_mesh.quads.size());
  for (Index e = 0; e < new_mesh.num_elements(); ++e) {
    const auto X = corners(new_mesh, new_x, e);
    for (int q = 0; q < 4; ++q) {
      const Vec2 p = map_point(X, kGaussPoints2x2[q][0], kGaussPoints2x2[q][1]);
      out[e][q] = interpolate(old_mesh, nodal, locate(old_mesh, old_x, grid, p));
    }
  }
  return out;
}

std::vector<Vec2> transfer_nodal_field(const Mesh& old_mesh, const std::vector<Vec2>& old_x,
                                       const std::vector<Vec2>& values, const std::vector<Vec2>& points) {
  const ElementGrid grid(old_mesh, old_x);
  std::vector<Vec2> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    out[i] = interpolate(old_mesh, values, locate(old_mesh, old_x, grid, points[i]));
  return out;
}

std::function<double(const Vec2&)> nodal_field(const Mesh& m, const std::vector<Vec2>& x,
                                               const std::vector<double>& values) {
  struct Held {
    Mesh mesh;
    std::vector<Vec2> x;
    std::vector<double> values;
    ElementGrid grid;
  };
  Mesh quads;
  quads.quads = m.quads;
  auto held = std::make_shared<const Held>(Held{quads, x, values, ElementGrid(m, x)});
  return [held](const Vec2& p) {
    return interpolate(held->mesh, held->values, locate(held->mesh, held->x, held->grid, p));
  };
}

}  // namespace rpfem
