#include "la/cholmod_llt.hpp"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "la/inline_openmp.hpp"

namespace rpfem {

// Eigen's wrapper keeps the factor protected: this reaches it.
struct CholmodLLT::Impl : Eigen::CholmodDecomposition<SpMat, Eigen::Lower> {
  cholmod_factor* factor() { return m_cholmodFactor; }
};

void set_kernel_options(cholmod_common& c) {
  c.print = 0;
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_AMD;
  c.postorder = 1;
}

CholmodLLT::CholmodLLT(Mode mode) : impl_(std::make_unique<Impl>()) {
  impl_->setMode(mode == Mode::Simplicial ? Eigen::CholmodSimplicialLLt
                 : mode == Mode::Auto     ? Eigen::CholmodAuto
                                          : Eigen::CholmodSupernodalLLt);
  set_kernel_options(impl_->cholmod());
}
CholmodLLT::~CholmodLLT() = default;

bool CholmodLLT::supernodal() const {
  cholmod_factor* L = impl_->factor();
  return L && L->is_super;
}

void CholmodLLT::analyze(const SpMat& A) {
  on_one_thread([&] { impl_->analyzePattern(A); });
  cholmod_factor* L = impl_->factor();
  if (!L || impl_->info() != Eigen::Success) throw std::runtime_error("CHOLMOD's symbolic analysis failed");
  perm_.clear(), gather_.clear();
  S_ = SpMat();
  rows_ = A.rows(), nonzeros_ = A.nonZeros();
  // A simplicial factor keeps CHOLMOD's own path: cholmod_rowfac needs
  // triu(S), a transpose of tril even in the natural ordering, and it sums
  // its updates in an order that follows the order of S's entries, which
  // cholmod_ptranspose does not leave sorted (its factor would not be
  // CHOLMOD's to the bit).
  if (!L->is_super) return;
  const int n = static_cast<int>(A.rows());
  // Keep CHOLMOD's ordering (fill-reducing, postordered) and make the
  // factor's own the identity: cholmod_factorize then takes S as given,
  // and cholmod_solve permutes nothing (CHOLMOD_NATURAL: Perm unused).
  int* Perm = static_cast<int*>(L->Perm);
  perm_.assign(Perm, Perm + n);
  std::iota(Perm, Perm + n, 0);
  L->ordering = CHOLMOD_NATURAL;
  // S = tril(P A P^T): A's (i, j), i >= j, is S's (max, min) of (q_i, q_j),
  // q the inverse ordering; per column of S its rows sorted, as
  // cholmod_ptranspose leaves them. cholmod_super_numeric copies each entry
  // of S into its supernode, so their order within a column does not
  // change the factor.
  std::vector<int> q(n);
  for (int k = 0; k < n; ++k) q[perm_[k]] = k;
  struct Entry {
    int col, row, src;
  };
  std::vector<Entry> entries;
  entries.reserve((A.nonZeros() + n) / 2);
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const int* count = A.innerNonZeroPtr();  // not null: A is not compressed
  for (int j = 0; j < n; ++j)
    for (int p = outer[j]; p < (count ? outer[j] + count[j] : outer[j + 1]); ++p) {
      const int i = inner[p];
      if (i < j) continue;
      entries.push_back({std::min(q[i], q[j]), std::max(q[i], q[j]), p});
    }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.col != b.col ? a.col < b.col : a.row < b.row; });
  S_ = SpMat(n, n);
  S_.resizeNonZeros(static_cast<Index>(entries.size()));
  int* so = S_.outerIndexPtr();
  std::fill(so, so + n + 1, 0);
  gather_.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    ++so[entries[k].col + 1];
    S_.innerIndexPtr()[k] = entries[k].row;
    gather_[k] = entries[k].src;
  }
  std::partial_sum(so, so + n + 1, so);
}

bool CholmodLLT::factorize(const SpMat& A) {
  if (A.rows() != rows_ || A.nonZeros() != nonzeros_)
    throw std::logic_error("CholmodLLT::factorize: the matrix is not of the analyzed pattern");
  if (perm_.empty()) {  // simplicial: CHOLMOD's own path
    on_one_thread([&] { impl_->factorize(A); });
    return impl_->info() == Eigen::Success;
  }
  const double* a = A.valuePtr();
  double* s = S_.valuePtr();
  for (std::size_t k = 0; k < gather_.size(); ++k) s[k] = a[gather_[k]];
  on_one_thread([&] { impl_->factorize(S_); });
  return impl_->info() == Eigen::Success;
}

Vec CholmodLLT::solve(const Vec& b) {
  Vec x;
  if (perm_.empty()) {
    on_one_thread([&] { x = impl_->solve(b); });
    return x;
  }
  const int n = static_cast<int>(perm_.size());
  Vec y(n), z;
  for (int k = 0; k < n; ++k) y(k) = b(perm_[k]);  // P b
  on_one_thread([&] { z = impl_->solve(y); });
  x.resize(n);
  for (int k = 0; k < n; ++k) x(perm_[k]) = z(k);  // P^T z
  return x;
}

double CholmodLLT::rcond() {
  cholmod_factor* L = impl_->factor();
  return L ? cholmod_rcond(L, &impl_->cholmod()) : 0.0;
}

}  // namespace rpfem
