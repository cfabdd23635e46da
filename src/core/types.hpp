// Basic numeric types shared by the whole kernel. Units inside rpfem:
// mm, N, MPa (= N/mm^2), s.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rpfem {

using Index = std::int64_t;
using Vec = Eigen::VectorXd;
using Vec2 = Eigen::Vector2d;
using Mat = Eigen::MatrixXd;
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// 1 kgf/mm^2 = 9.80665 N/mm^2 (MPa): the paper's units are converted at input.
inline constexpr double kKgfPerMm2ToMPa = 9.80665;
inline constexpr double kPi = 3.14159265358979323846;

enum class Geometry { Axisymmetric, PlaneStrain };

// The cross product of two plane vectors (its z component): > 0 when b
// turns left from a.
inline double cross(const Vec2& a, const Vec2& b) { return a(0) * b(1) - a(1) * b(0); }

// Error in user input (case file, command line): the driver prints what()
// on one line and exits with code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rpfem
