// Comparing two load-stroke curves (paper Test II: the virtual rigid body's
// ram load against the rigid die's). Curve B is piecewise linear in stroke.
#pragma once
#include <vector>

namespace rpfem {

// F at x on the piecewise linear curve (s, F), s non-decreasing; the end
// values beyond its ends.
double interpolate_linear(const std::vector<double>& s, const std::vector<double>& F, double x);

struct CurveDifference {
  double worst = 0;      // largest relative difference found
  double at_stroke = 0;  // mm, where
  int points = 0;        // points of A compared
};

// Over A's points with stroke in [from, B's last stroke]: the distance of
// F_A(s) to the band of B's loads over [s - stroke_tolerance, s +
// stroke_tolerance], relative to |F_B(s)|. With stroke_tolerance = 0 it is
// |F_A(s) - F_B(s)| / |F_B(s)|. A tolerance of one stroke increment
// compares curves that are staircases early on (a ring of nodes lands
// within a step in one run and at a step's end in the other) by their
// shape rather than by where each step of the staircase falls.
CurveDifference curve_difference(const std::vector<double>& stroke_a, const std::vector<double>& load_a,
                                 const std::vector<double>& stroke_b, const std::vector<double>& load_b,
                                 double from, double stroke_tolerance);

// The largest jump of a load-stroke curve: over its steps i from `from`
// mm with a step on either side, the step's change of load beyond the trend
// of its neighbours, |dF_i - ds_i (dF_{i-1} + dF_{i+1}) / (ds_{i-1} + ds_{i+1})|,
// relative to |F| at the step's end. A smooth curve scores its third
// difference (zero on a parabola, with equal steps); a load that drops or
// leaps within one step (a role switch, a ring of nodes landing) scores
// the jump.
CurveDifference curve_jump(const std::vector<double>& stroke, const std::vector<double>& load, double from);

}  // namespace rpfem
