#include "la/inline_openmp.hpp"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>

namespace rpfem {

namespace {

thread_local bool regions_inline = false;
std::atomic<std::uint64_t> regions_inlined{0};

using GompParallel = void (*)(void (*)(void*), void*, unsigned, unsigned);

// libgomp's own GOMP_parallel, found past this program in the lookup order.
GompParallel libgomp_parallel() {
  static const GompParallel f = [] {
    void* s = dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0");
    if (!s) s = dlsym(RTLD_NEXT, "GOMP_parallel");
    return reinterpret_cast<GompParallel>(s);
  }();
  return f;
}

}  // namespace

InlineOpenMP::InlineOpenMP() : outer_(regions_inline) { regions_inline = true; }
InlineOpenMP::~InlineOpenMP() { regions_inline = outer_; }

std::uint64_t inline_openmp_regions() { return regions_inlined.load(std::memory_order_relaxed); }

}  // namespace rpfem

// `#pragma omp parallel` as GCC compiles it: fn(data) on a team of
// num_threads (0: the default) threads (libgomp, parallel.c).
extern "C" void GOMP_parallel(void (*fn)(void*), void* data, unsigned num_threads, unsigned flags) {
  if (rpfem::regions_inline) {
    rpfem::regions_inlined.fetch_add(1, std::memory_order_relaxed);
    fn(data);
    return;
  }
  const rpfem::GompParallel real = rpfem::libgomp_parallel();
  if (!real) std::abort();  // only libgomp's callers come here, and they link it
  real(fn, data, num_threads, flags);
}
