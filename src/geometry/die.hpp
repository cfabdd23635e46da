// Rigid dies: analytic profiles in the r-z (x-y) plane, chains of line
// segments and circular arcs, moving by a prescribed velocity. A die is not
// meshed. Shared by the contact formulations (the kernel never uses it).
//
// A profile is given by vertices walked with the die material on the LEFT,
// so the outward normal n = (d_y, -d_x) of the walking direction d points
// to the workpiece (a top punch is walked left to right, a bottom die right
// to left). Each interior vertex may carry a fillet radius: the corner is
// replaced by the tangent arc, so the die surface and its normal are
// continuous there; radius 0 keeps a sharp corner.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "material/friction_law.hpp"
#include "core/types.hpp"

namespace rpfem {

struct DiePiece {
  bool arc = false;
  Vec2 a = Vec2::Zero(), b = Vec2::Zero();  // end points, in walking order
  Vec2 center = Vec2::Zero();               // arcs
  double radius = 0;  // arcs
  bool convex = true; // arcs: centre inside the die (a rounded punch edge)
};

struct DieProjection {
  Vec2 point = Vec2::Zero();   // closest point on the profile
  Vec2 normal = Vec2::Zero();  // outward (toward the workpiece), unit
  double distance = 0; // signed: > 0 outside the die, < 0 inside
  int piece = -1;
  bool at_vertex = false;  // closest point is a sharp corner or a profile end
};

// The tangent length of a fillet of radius r at vertex b between the
// segments a-b and b-c: r tan(theta / 2), theta the turn between them (0
// where they are collinear); the arc runs from b back along a-b by this
// much to b on along b-c by as much.
double fillet_tangent_length(const Vec2& a, const Vec2& b, const Vec2& c, double r);

class DieProfile {
 public:
  DieProfile() = default;
  // vertices.size() >= 2; fillets.size() == vertices.size() (first and last
  // ignored) or empty. Throws std::invalid_argument on a fillet that does
  // not fit between its neighbours.
  DieProfile(const std::vector<Vec2>& vertices, const std::vector<double>& fillets);
  // Closest point of the profile translated by `shift`.
  DieProjection project(const Vec2& p, const Vec2& shift = Vec2::Zero()) const;
  const std::vector<DiePiece>& pieces() const { return pieces_; }
  // The profile's corners, translated by `shift`: each interior vertex where
  // two segments meet at a sharp corner, and points along each fillet arc
  // (its ends and every 10 degrees between); the profile's two ends too if
  // `with_ends`.
  std::vector<Vec2> corner_points(const Vec2& shift, bool with_ends) const;
  // The whole profile as a polyline in walking order, translated by
  // `shift`: the segments' ends, and along each arc chords that stray from
  // it by at most `sagitta` (mm) (at most a quarter and at least a
  // thousandth of a turn each). For drawing the die.
  std::vector<Vec2> polyline(const Vec2& shift, double sagitta) const;

 private:
  std::vector<DiePiece> pieces_;
};

// Die velocity: constant, or piecewise linear in time from a table
// (t, vx, vy), held constant past its ends.
class DieMotion {
 public:
  DieMotion() = default;
  explicit DieMotion(Vec2 constant) : table_{{0.0, constant(0), constant(1)}} {}
  explicit DieMotion(std::vector<std::array<double, 3>> table);  // sorted by t
  Vec2 velocity(double t) const;
  // Displacement from t = 0 to t (exact integral of the table).
  Vec2 displacement(double t) const;
  double max_speed() const;

 private:
  std::vector<std::array<double, 3>> table_;
};

struct Die {
  std::string name;
  DieProfile profile;
  DieMotion motion;
  FrictionLaw friction;  // on the die's contact surface
  DieProjection project(const Vec2& p, double t) const { return profile.project(p, motion.displacement(t)); }
};

}  // namespace rpfem
