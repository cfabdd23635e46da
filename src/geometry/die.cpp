#include "geometry/die.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace rpfem {

namespace {
Vec2 right_normal(const Vec2& d) { return Vec2(d(1), -d(0)); }
}  // namespace

double fillet_tangent_length(const Vec2& a, const Vec2& b, const Vec2& c, double r) {
  const Vec2 d1 = (b - a).normalized(), d2 = (c - b).normalized();
  const double turn = std::atan2(cross(d1, d2), d1.dot(d2));
  return std::abs(turn) < 1e-12 ? 0.0 : r * std::tan(std::abs(turn) / 2);
}

DieProfile::DieProfile(const std::vector<Vec2>& v, const std::vector<double>& fillets) {
  if (v.size() < 2) throw std::invalid_argument("a die profile needs at least two vertices");
  if (!fillets.empty() && fillets.size() != v.size())
    throw std::invalid_argument("give one fillet radius per vertex (or none)");
  // Trim each straight edge by the tangent lengths of the fillets at its ends.
  std::vector<Vec2> start(v.begin(), v.end() - 1), end(v.begin() + 1, v.end());
  std::vector<DiePiece> arcs(v.size());
  std::vector<bool> has_arc(v.size(), false);
  for (std::size_t i = 1; i + 1 < v.size(); ++i) {
    const double r = fillets.empty() ? 0.0 : fillets[i];
    if (r <= 0) continue;
    const Vec2 d1 = (v[i] - v[i - 1]).normalized(), d2 = (v[i + 1] - v[i]).normalized();
    const double turn = std::atan2(cross(d1, d2), d1.dot(d2));  // > 0: left turn, convex die corner
    if (std::abs(turn) < 1e-12) continue;
    const double t = fillet_tangent_length(v[i - 1], v[i], v[i + 1], r);
    if (t > (v[i] - v[i - 1]).norm() + 1e-12 || t > (v[i + 1] - v[i]).norm() + 1e-12)
      throw std::invalid_argument("fillet radius too large for the neighbouring edges at vertex " + std::to_string(i));
    DiePiece a;
    a.arc = true;
    a.a = v[i] - t * d1;
    a.b = v[i] + t * d2;
    a.convex = turn > 0;
    a.radius = r;
    // Centre on the left of d1 for a left turn (inside the die), on the right otherwise.
    a.center = a.a + (a.convex ? -right_normal(d1) : right_normal(d1)) * r;
    end[i - 1] = a.a;
    start[i] = a.b;
    arcs[i] = a;
    has_arc[i] = true;
  }
  for (std::size_t i = 0; i + 1 < v.size(); ++i) {
    if (i > 0 && has_arc[i]) pieces_.push_back(arcs[i]);
    DiePiece s;
    s.a = start[i];
    s.b = end[i];
    if ((s.b - s.a).norm() > 1e-14) pieces_.push_back(s);
  }
}

namespace {

// Points along a fillet arc, translated by `shift`: its end b and n - 1
// points between, n steps of equal angle no larger than max_step (rad);
// its start a too if with_start.
void arc_points(const DiePiece& piece, const Vec2& shift, double max_step, bool with_start, std::vector<Vec2>& p) {
  const double a0 = std::atan2(piece.a(1) - piece.center(1), piece.a(0) - piece.center(0));
  double sweep = std::atan2(piece.b(1) - piece.center(1), piece.b(0) - piece.center(0)) - a0;
  // A fillet turns by less than half a turn: the short way round.
  if (sweep > kPi) sweep -= 2 * kPi;
  if (sweep < -kPi) sweep += 2 * kPi;
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(sweep) / max_step)));
  for (int i = with_start ? 0 : 1; i <= n; ++i) {
    const double a = a0 + sweep * i / n;
    p.push_back(piece.center + shift + piece.radius * Vec2(std::cos(a), std::sin(a)));
  }
}

}  // namespace

std::vector<Vec2> DieProfile::corner_points(const Vec2& shift, bool with_ends) const {
  std::vector<Vec2> p;
  if (pieces_.empty()) return p;
  if (with_ends) p.push_back(pieces_.front().a + shift);
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    const DiePiece& piece = pieces_[k];
    if (piece.arc) {
      arc_points(piece, shift, kPi / 18, true, p);
    } else if (k + 1 < pieces_.size() && !pieces_[k + 1].arc) {
      p.push_back(piece.b + shift);  // two segments meet: a sharp corner
    }
  }
  if (with_ends) p.push_back(pieces_.back().b + shift);
  return p;
}

std::vector<Vec2> DieProfile::polyline(const Vec2& shift, double sagitta) const {
  std::vector<Vec2> p;
  if (pieces_.empty()) return p;
  p.push_back(pieces_.front().a + shift);
  for (const DiePiece& piece : pieces_) {
    if (!piece.arc) {
      p.push_back(piece.b + shift);
      continue;
    }
    // A chord of angle t is off its arc by r (1 - cos(t / 2)); at most a
    // quarter turn per chord, at least a thousandth of a turn.
    const double s = std::clamp(sagitta / piece.radius, 0.0, 1.0);
    arc_points(piece, shift, std::clamp(2 * std::acos(1 - s), kPi / 500, kPi / 2), false, p);
  }
  return p;
}

DieProjection DieProfile::project(const Vec2& p, const Vec2& shift) const {
  DieProjection best;
  double best_d2 = INFINITY;
  std::vector<Vec2> piece_normal_at_a(pieces_.size()), piece_normal_at_b(pieces_.size());
  for (std::size_t k = 0; k < pieces_.size(); ++k) {
    const DiePiece& c = pieces_[k];
    const Vec2 a = c.a + shift, b = c.b + shift;
    Vec2 q, n;
    bool vertex = false;
    if (!c.arc) {
      const Vec2 d = (b - a).normalized();
      n = right_normal(d);
      const double s = std::clamp((p - a).dot(d), 0.0, (b - a).norm());
      q = a + s * d;
      vertex = s <= 0.0 || s >= (b - a).norm();
    } else {
      const Vec2 C = c.center + shift;
      const Vec2 ra = (a - C) / c.radius, rb = (b - C) / c.radius;
      Vec2 rp = p - C;
      if (rp.norm() < 1e-14) rp = ra;
      rp.normalize();
      // Inside the arc's sweep: between ra and rb (sweep < pi for a fillet).
      const bool inside = cross(ra, rp) * cross(ra, rb) >= 0 && cross(rp, rb) * cross(ra, rb) >= 0 && rp.dot(ra + rb) > 0;
      if (inside) {
        q = C + c.radius * rp;
      } else {
        q = (p - a).squaredNorm() < (p - b).squaredNorm() ? a : b;
      }
      n = c.convex ? Vec2((q - C) / c.radius) : Vec2((C - q) / c.radius);
    }
    const double d2 = (p - q).squaredNorm();
    if (d2 < best_d2 - 1e-24) {
      best_d2 = d2;
      best.point = q;
      best.normal = n;
      best.piece = static_cast<int>(k);
      best.at_vertex = vertex;
    }
  }
  const Vec2 r = p - best.point;
  const double dist = std::sqrt(best_d2);
  if (!best.at_vertex || dist < 1e-14) {
    best.distance = r.dot(best.normal);
    return best;
  }
  // The closest point is a sharp corner (or an end): outside is the union of
  // the neighbours' outer half-planes at a convex corner, their intersection
  // at a concave one; the normal points from the corner to p.
  const DiePiece& c = pieces_[best.piece];
  const bool at_a = (best.point - (c.a + shift)).norm() < 1e-12;
  const int other = at_a ? best.piece - 1 : best.piece + 1;
  auto normal_of = [&](int k) {
    const DiePiece& e = pieces_[k];
    return right_normal((e.b - e.a).normalized());
  };
  const Vec2 n1 = normal_of(best.piece);
  bool outside = r.dot(n1) > 0;
  if (other >= 0 && other < static_cast<int>(pieces_.size()) && !pieces_[other].arc) {
    const Vec2 n2 = normal_of(other);
    const Vec2 din = at_a ? (pieces_[other].b - pieces_[other].a) : (c.b - c.a);
    const Vec2 dout = at_a ? (c.b - c.a) : (pieces_[other].b - pieces_[other].a);
    const bool convex = cross(din, dout) > 0;
    outside = convex ? (r.dot(n1) > 0 || r.dot(n2) > 0) : (r.dot(n1) > 0 && r.dot(n2) > 0);
  }
  best.distance = outside ? dist : -dist;
  best.normal = outside ? Vec2(r / dist) : Vec2(-r / dist);
  return best;
}

DieMotion::DieMotion(std::vector<std::array<double, 3>> table) : table_(std::move(table)) {
  if (table_.empty()) throw std::invalid_argument("empty velocity table");
  for (std::size_t i = 1; i < table_.size(); ++i)
    if (!(table_[i][0] > table_[i - 1][0])) throw std::invalid_argument("velocity table times must increase");
}

Vec2 DieMotion::velocity(double t) const {
  if (t <= table_.front()[0]) return Vec2(table_.front()[1], table_.front()[2]);
  for (std::size_t i = 1; i < table_.size(); ++i)
    if (t <= table_[i][0]) {
      const double w = (t - table_[i - 1][0]) / (table_[i][0] - table_[i - 1][0]);
      return Vec2((1 - w) * table_[i - 1][1] + w * table_[i][1], (1 - w) * table_[i - 1][2] + w * table_[i][2]);
    }
  return Vec2(table_.back()[1], table_.back()[2]);
}

Vec2 DieMotion::displacement(double t) const {
  // Exact integral of the piecewise-linear velocity (constant outside).
  Vec2 u = Vec2::Zero();
  double t0 = 0;
  std::vector<double> knots{0.0};
  for (const auto& r : table_)
    if (r[0] > 0 && r[0] < t) knots.push_back(r[0]);
  knots.push_back(t);
  for (std::size_t i = 1; i < knots.size(); ++i) {
    const double t1 = knots[i];
    u += 0.5 * (t1 - t0) * (velocity(t0) + velocity(t1));
    t0 = t1;
  }
  return u;
}

double DieMotion::max_speed() const {
  double s = 0;
  for (const auto& r : table_) s = std::max(s, std::hypot(r[1], r[2]));
  return s;
}

}  // namespace rpfem
