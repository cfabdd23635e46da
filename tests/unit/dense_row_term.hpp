// A row's term with its gradient and Hessian written out over the row's
// nodes (contact/row_terms.hpp expand()), for the derivative checks.
#pragma once
#include <array>
#include <vector>

#include "contact/row_terms.hpp"

namespace rpfem::unit {

struct DenseRowTerm : RowTerm {
  std::vector<double> grad, hess;  // 2k, and 2k x 2k column-major
};

// vel: the velocities of nodes 0, 1, ... (the row's nodes index into it).
inline DenseRowTerm dense_row_term(const PairKinematics& k, const RowLaw& l, const std::vector<Vec2>& vel) {
  DenseRowTerm d;
  static_cast<RowTerm&>(d) = row_term(k, l, vel);
  d.grad.resize(2 * k.k);
  d.hess.resize(4 * k.k * k.k);
  expand(k, d, d.grad.data(), d.hess.data());
  return d;
}

template <std::size_t N>
DenseRowTerm dense_row_term(const PairKinematics& k, const RowLaw& l, const std::array<Vec2, N>& v) {
  return dense_row_term(k, l, std::vector<Vec2>(v.begin(), v.end()));
}

}  // namespace rpfem::unit
