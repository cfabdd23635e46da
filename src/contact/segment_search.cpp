#include "contact/segment_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <Eigen/Eigenvalues>

namespace rpfem {

Vec2 outward(const Vec2& d) { return Vec2(d(1), -d(0)).normalized(); }

double mean_edge_length(const std::vector<Vec2>& x, const ContactSurface& s) {
  double sum = 0;
  for (const Edge& e : s.edges) sum += (x[e.b] - x[e.a]).norm();
  return s.edges.empty() ? 0.0 : sum / static_cast<double>(s.edges.size());
}

ContactSurface ContactSurface::from_sides(const Mesh& mesh, const std::vector<std::string>& sides) {
  ContactSurface s;
  std::set<std::pair<Index, Index>> seen;
  for (const auto& name : sides)
    for (const Edge& e : mesh.sides.at(name)) {
      if (!seen.insert({e.a, e.b}).second) continue;
      s.edges.push_back(e);
      s.nodes.push_back(e.a);
      s.nodes.push_back(e.b);
      s.body = mesh.node_body[e.a];
    }
  std::sort(s.nodes.begin(), s.nodes.end());
  s.nodes.erase(std::unique(s.nodes.begin(), s.nodes.end()), s.nodes.end());
  return s;
}

SegmentGrid::SegmentGrid(const std::vector<Vec2>& x, const ContactSurface& master, double margin) {
  if (master.edges.empty()) return;
  Vec2 lo = x[master.edges[0].a], hi = lo;
  double total = 0;
  for (const Edge& e : master.edges) {
    lo = lo.cwiseMin(x[e.a]).cwiseMin(x[e.b]);
    hi = hi.cwiseMax(x[e.a]).cwiseMax(x[e.b]);
    total += (x[e.b] - x[e.a]).norm();
  }
  lo.array() -= margin;
  hi.array() += margin;
  // Cells about the mean segment length (and no smaller than the margin),
  // at most ~4 per segment so a long thin surface stays cheap.
  cell_ = std::max(total / master.edges.size(), margin);
  const Vec2 span = hi - lo;
  const double max_cells = 4.0 * master.edges.size() + 16;
  if (span(0) / cell_ * span(1) / cell_ > max_cells) cell_ = std::sqrt(span(0) * span(1) / max_cells);
  cell_ = std::max(cell_, 1e-12 * std::max(span(0), span(1)) + 1e-300);
  lo_ = lo;
  nx_ = std::max(1, static_cast<int>(std::ceil(span(0) / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(span(1) / cell_)));
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (int k = 0; k < static_cast<int>(master.edges.size()); ++k) {
    const Edge& e = master.edges[k];
    const Vec2 a = x[e.a].cwiseMin(x[e.b]).array() - margin, b = x[e.a].cwiseMax(x[e.b]).array() + margin;
    const int i0 = std::clamp(static_cast<int>((a(0) - lo_(0)) / cell_), 0, nx_ - 1);
    const int i1 = std::clamp(static_cast<int>((b(0) - lo_(0)) / cell_), 0, nx_ - 1);
    const int j0 = std::clamp(static_cast<int>((a(1) - lo_(1)) / cell_), 0, ny_ - 1);
    const int j1 = std::clamp(static_cast<int>((b(1) - lo_(1)) / cell_), 0, ny_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(k);
  }
}

void SegmentGrid::candidates(const Vec2& p, std::vector<int>& out) const {
  out.clear();
  if (cells_.empty()) return;
  const double fi = (p(0) - lo_(0)) / cell_, fj = (p(1) - lo_(1)) / cell_;
  if (!(fi >= 0 && fj >= 0 && fi < nx_ && fj < ny_)) return;
  const auto& c = cells_[static_cast<std::size_t>(fj) * nx_ + static_cast<std::size_t>(fi)];
  out.assign(c.begin(), c.end());
}

LeastSquaresLine least_squares_line(const Vec2& p, const Vec2& a, const Vec2& b) {
  // Total least squares: the line through the centroid along the principal
  // direction of the three points' scatter.
  const Vec2 c = (p + a + b) / 3.0;
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  for (const Vec2* q : {&p, &a, &b}) S += (*q - c) * (*q - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
  Vec2 t = eig.eigenvectors().col(1);  // largest eigenvalue
  if (t.dot(b - a) < 0) t = -t;
  LeastSquaresLine out;
  out.normal = Vec2(t(1), -t(0));
  const double xa = t.dot(a - c), xb = t.dot(b - c), xp = t.dot(p - c);
  out.xi = std::clamp((xp - xa) / (xb - xa), 0.0, 1.0);
  return out;
}

std::vector<Vec2> node_normals(const std::vector<Vec2>& x, const ContactSurface& s) {
  std::vector<Vec2> n(s.nodes.size(), Vec2::Zero());
  for (const Edge& e : s.edges) {
    const Vec2 d = x[e.b] - x[e.a];
    if (!(d.norm() > 0)) continue;
    n[s.local(e.a)] += outward(d);
    n[s.local(e.b)] += outward(d);
  }
  for (Vec2& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

std::optional<SegmentHit> find_segment(const std::vector<Vec2>& x, const ContactSurface& master,
                                       const SegmentGrid& grid, const Vec2& p, double capture,
                                       const Vec2& slave_normal) {
  std::vector<int> cand;
  grid.candidates(p, cand);
  // Segments shorter than this are slivers: their direction is round-off.
  double longest = 0;
  for (int k : cand) longest = std::max(longest, (x[master.edges[k].b] - x[master.edges[k].a]).norm());
  const double sliver = 1e-8 * longest;
  // Segments S lies over (with a margin of kEnd of their length past
  // either end, so a node landing on a vertex with round-off sees both).
  constexpr double kEnd = 0.05;
  struct Option {
    SegmentHit hit;
    double facing = 0, inner = 0, length = 0;
  };
  std::vector<Option> over;
  for (int k : cand) {
    const Vec2 &A = x[master.edges[k].a], &B = x[master.edges[k].b];
    const Vec2 d = B - A;
    const double L = d.norm();
    if (!(L > sliver)) continue;
    const double area2 = cross(d, p - A);  // twice the signed area of (A, B, S)
    const double g = -area2 / L;
    const double s = (p - A).dot(d) / (L * L);
    if (s < -kEnd || s > 1 + kEnd || std::abs(g) > capture) continue;
    Option o;
    o.hit.edge = k;
    o.hit.gap = g;
    o.hit.xi = std::clamp(s, 0.0, 1.0);
    o.hit.point = A + o.hit.xi * d;
    o.facing = -slave_normal.dot(outward(d));
    o.inner = std::min(s, 1 - s);
    o.length = L;
    over.push_back(o);
  }
  // The closest; among those about as close (within 1e-3 of a segment
  // length: S on or next to a shared vertex, where the master surface has
  // a kink at the edge of a contact zone) the one facing the slave surface
  // best, then the one S lies deeper over.
  const Option* pick = nullptr;
  double closest = std::numeric_limits<double>::infinity();
  for (const Option& o : over) closest = std::min(closest, std::abs(o.hit.gap));
  for (const Option& o : over) {
    if (std::abs(o.hit.gap) > closest + 1e-3 * o.length) continue;
    if (!pick || o.facing > pick->facing + 1e-9 ||
        (o.facing >= pick->facing - 1e-9 && o.inner > pick->inner))
      pick = &o;
  }
  std::optional<SegmentHit> best;
  if (pick) best = pick->hit;
  if (best) {
    const Edge& e = master.edges[best->edge];
    const LeastSquaresLine ls = least_squares_line(p, x[e.a], x[e.b]);
    const Vec2 n_seg = outward(x[e.b] - x[e.a]);
    // The fitted line follows the segment unless S is far off it relative
    // to the segment's length (then the fit tilts toward S): beyond 30
    // degrees the segment itself is the master surface.
    if (ls.normal.dot(n_seg) > std::cos(M_PI / 6)) {
      best->normal = ls.normal;
      best->xi = ls.xi;
    } else {
      best->normal = n_seg;
    }
    return best;
  }
  // Over no segment: the nearest vertex within reach, its normal the mean
  // of its (non-sliver) segments' normals.
  double dmin = std::numeric_limits<double>::infinity();
  Index vertex = -1;
  for (int k : cand)
    for (Index n : {master.edges[k].a, master.edges[k].b}) {
      const double dist = (p - x[n]).norm();
      if (dist < dmin) dmin = dist, vertex = n;
    }
  if (vertex < 0 || dmin > capture) return std::nullopt;
  Vec2 n_sum = Vec2::Zero();
  int edge = -1;
  double edge_len = 0;
  for (int k : cand) {
    const Edge& e = master.edges[k];
    if (e.a != vertex && e.b != vertex) continue;
    const double L = (x[e.b] - x[e.a]).norm();
    if (!(L > sliver)) continue;
    n_sum += outward(x[e.b] - x[e.a]);
    if (L > edge_len) edge_len = L, edge = k;
  }
  if (edge < 0 || !(n_sum.norm() > 0)) return std::nullopt;
  SegmentHit h;
  h.edge = edge;
  h.xi = master.edges[edge].a == vertex ? 0.0 : 1.0;
  h.normal = n_sum.normalized();
  h.point = x[vertex];
  h.gap = h.normal.dot(p - x[vertex]);
  h.at_vertex = true;
  return h;
}

std::vector<std::optional<SegmentHit>> find_segments(const std::vector<Vec2>& x, const ContactSurface& slave,
                                                     const ContactSurface& master, const SegmentGrid& grid,
                                                     double capture) {
  const std::vector<Vec2> normals = node_normals(x, slave);
  std::vector<std::optional<SegmentHit>> hits(slave.nodes.size());
  for (std::size_t l = 0; l < slave.nodes.size(); ++l)
    hits[l] = find_segment(x, master, grid, x[slave.nodes[l]], capture, normals[l]);
  return hits;
}

}  // namespace rpfem
