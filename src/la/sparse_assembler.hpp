// Assembly of nodal element blocks into a fixed-pattern sparse matrix in the
// reduced unknowns of a DofMap. The pattern is built once per layout (mesh,
// constraints, contact couplings) and reused: assembly then only adds values,
// and the linear solver keeps its symbolic factorization.
#pragma once
#include <array>
#include <vector>

#include "core/types.hpp"
#include "fem/dof_map.hpp"

namespace rpfem {

class SparseAssembler {
 public:
  // Every clique couples all unknowns of its nodes.
  void build(const DofMap& dofs, const std::vector<std::array<Index, 4>>& quads,
             const std::vector<std::vector<Index>>& extra_cliques);
  // Incremented each time build() makes a new pattern.
  std::uint64_t pattern_version() const { return version_; }

  void set_zero();
  // Adds the nodal block K (2k x 2k, column-major, global x/y components of
  // nodes[0..k)) transformed to the nodes' frames: A += T^T K T.
  void add(const Index* nodes, int k, const double* K);
  // The same for quads[e] of the last build(), through the value positions
  // found then (add() searches each entry's row in its column; the quads
  // are most of the tangent's blocks). The sums are add()'s, bit for bit.
  void add_quad(Index e, const Index* nodes, const double* K);
  SpMat& matrix() { return A_; }
  const SpMat& matrix() const { return A_; }

 private:
  const DofMap* dofs_ = nullptr;
  SpMat A_;
  std::uint64_t version_ = 0;
  // Per quad of the last build, the value position of each (column node b,
  // row node a, free direction j, free direction i): [64 e + 16 b + 4 a +
  // 2 j + i]; -1 where a direction is not free.
  std::vector<int> quad_pos_;
  std::vector<std::array<Index, 4>> quads_;  // their nodes: another quad e is added by add()

  int position(Index row, Index col) const;
  // A += T^T K T for the nodal block K (2k x 2k, column-major), each entry
  // (column node b, row node a, free directions j, i; reduced row and
  // column) at the value position where(b, a, j, i, row, col).
  template <class Where>
  void scatter(const Index* nodes, int k, const double* K, Where where) {
    const int ld = 2 * k;
    double* val = A_.valuePtr();
    for (int b = 0; b < k; ++b) {
      const NodeFrame& fb = dofs_->frame(nodes[b]);
      if (fb.nfree == 0) continue;
      for (int a = 0; a < k; ++a) {
        const NodeFrame& fa = dofs_->frame(nodes[a]);
        if (fa.nfree == 0) continue;
        const double* Kb = K + (2 * b) * ld + 2 * a;  // the block's first column
        if (fa.nfree == 2 && fb.nfree == 2) {
          // Two free nodes: T = I (dof_map.cpp), so T^T K T is K itself,
          // products with 1 and sums with 0 left out.
          for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) val[where(b, a, j, i, fa.dof[i], fb.dof[j])] += Kb[j * ld + i];
          continue;
        }
        Eigen::Matrix2d Kab;
        Kab << Kb[0], Kb[ld], Kb[1], Kb[ld + 1];
        const Eigen::Matrix2d R = fa.T.transpose() * Kab * fb.T;
        for (int j = 0; j < fb.nfree; ++j)
          for (int i = 0; i < fa.nfree; ++i) val[where(b, a, j, i, fa.dof[i], fb.dof[j])] += R(i, j);
      }
    }
  }
};

}  // namespace rpfem
