#include "la/sparse_assembler.hpp"

#include <algorithm>
#include <stdexcept>

namespace rpfem {

void SparseAssembler::build(const DofMap& dofs, const std::vector<std::array<Index, 4>>& quads,
                            const std::vector<std::vector<Index>>& extra_cliques) {
  dofs_ = &dofs;
  const Index n = dofs.num_free();
  std::vector<std::vector<int>> cols(static_cast<std::size_t>(n));
  std::vector<Index> clique_dofs;
  auto add_clique = [&](const Index* nodes, std::size_t k) {
    clique_dofs.clear();
    for (std::size_t a = 0; a < k; ++a) {
      const NodeFrame& f = dofs.frame(nodes[a]);
      for (int i = 0; i < f.nfree; ++i) clique_dofs.push_back(f.dof[i]);
    }
    for (Index c : clique_dofs)
      for (Index r : clique_dofs) cols[c].push_back(static_cast<int>(r));
  };
  for (const auto& q : quads) add_clique(q.data(), 4);
  for (const auto& c : extra_cliques) add_clique(c.data(), c.size());

  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
  for (Index c = 0; c < n; ++c) {
    auto& v = cols[c];
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    outer[c + 1] = outer[c] + static_cast<int>(v.size());
  }
  A_ = SpMat(n, n);
  A_.resizeNonZeros(outer[n]);
  std::copy(outer.begin(), outer.end(), A_.outerIndexPtr());
  for (Index c = 0; c < n; ++c) std::copy(cols[c].begin(), cols[c].end(), A_.innerIndexPtr() + outer[c]);
  set_zero();
  ++version_;
}

void SparseAssembler::set_zero() { std::fill_n(A_.valuePtr(), A_.nonZeros(), 0.0); }

void SparseAssembler::add(const Index* nodes, int k, const double* K) {
  const int ld = 2 * k;
  const int* outer = A_.outerIndexPtr();
  const int* inner = A_.innerIndexPtr();
  double* val = A_.valuePtr();
  for (int b = 0; b < k; ++b) {
    const NodeFrame& fb = dofs_->frame(nodes[b]);
    if (fb.nfree == 0) continue;
    for (int a = 0; a < k; ++a) {
      const NodeFrame& fa = dofs_->frame(nodes[a]);
      if (fa.nfree == 0) continue;
      Eigen::Matrix2d Kab;
      Kab << K[(2 * b) * ld + 2 * a], K[(2 * b + 1) * ld + 2 * a],
             K[(2 * b) * ld + 2 * a + 1], K[(2 * b + 1) * ld + 2 * a + 1];
      const Eigen::Matrix2d R = fa.T.transpose() * Kab * fb.T;
      for (int j = 0; j < fb.nfree; ++j) {
        const Index col = fb.dof[j];
        const int* begin = inner + outer[col];
        const int* end = inner + outer[col + 1];
        for (int i = 0; i < fa.nfree; ++i) {
          const int row = static_cast<int>(fa.dof[i]);
          const int* pos = std::lower_bound(begin, end, row);
          if (pos == end || *pos != row) throw std::logic_error("sparse assembly outside the pattern");
          val[pos - inner] += R(i, j);
        }
      }
    }
  }
}

}  // namespace rpfem
