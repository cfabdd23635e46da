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

  quads_ = quads;
  quad_pos_.assign(64 * quads.size(), -1);
  for (std::size_t e = 0; e < quads.size(); ++e)
    for (int b = 0; b < 4; ++b) {
      const NodeFrame& fb = dofs.frame(quads[e][b]);
      for (int a = 0; a < 4; ++a) {
        const NodeFrame& fa = dofs.frame(quads[e][a]);
        for (int j = 0; j < fb.nfree; ++j)
          for (int i = 0; i < fa.nfree; ++i)
            quad_pos_[64 * e + 16 * b + 4 * a + 2 * j + i] = position(fa.dof[i], fb.dof[j]);
      }
    }
}

int SparseAssembler::position(Index row, Index col) const {
  const int* inner = A_.innerIndexPtr();
  const int* begin = inner + A_.outerIndexPtr()[col];
  const int* end = inner + A_.outerIndexPtr()[col + 1];
  const int* pos = std::lower_bound(begin, end, static_cast<int>(row));
  if (pos == end || *pos != row) throw std::logic_error("sparse assembly outside the pattern");
  return static_cast<int>(pos - inner);
}

void SparseAssembler::add_quad(Index e, const Index* nodes, const double* K) {
  if (static_cast<std::size_t>(e) >= quads_.size() || !std::equal(nodes, nodes + 4, quads_[e].begin())) {
    add(nodes, 4, K);
    return;
  }
  const int* pos = quad_pos_.data() + 64 * e;
  scatter(nodes, 4, K, [pos](int b, int a, int j, int i, Index, Index) { return pos[16 * b + 4 * a + 2 * j + i]; });
}

void SparseAssembler::set_zero() { std::fill_n(A_.valuePtr(), A_.nonZeros(), 0.0); }

void SparseAssembler::add(const Index* nodes, int k, const double* K) {
  scatter(nodes, k, K, [this](int, int, int, int, Index row, Index col) { return position(row, col); });
}

}  // namespace rpfem
