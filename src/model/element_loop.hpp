// The element loops of the kernel (residual, tangent, energy) run over
// threads in two phases: each element's terms into its own slot (any
// thread, any order), then their sums in element order on one thread. A
// sum's order is then the serial loop's whatever the thread count, so the
// results are the same bits with one thread or many.
#pragma once
#include "core/types.hpp"

namespace rpfem {

// Below this many elements the loop stays on one thread (its cost is then
// about the threads' start).
constexpr Index kParallelElements = 512;

// Whether for_each_element(n, threads, f) calls f in element order on the
// calling thread.
inline bool element_loop_is_serial(Index n, int threads) { return threads <= 1 || n < kParallelElements; }

// Calls f(e) for e in [0, n), over `threads` threads (OpenMP, static
// schedule). f must write only what belongs to element e, unless the loop
// is serial (element_loop_is_serial).
// A serial loop does not enter OpenMP at all: a parallel construct whose
// if clause is false still starts and ends a team of one, whose end is a
// futex call (la/inline_openmp.hpp).
template <class F>
void for_each_element(Index n, int threads, F&& f) {
  if (element_loop_is_serial(n, threads)) {
    for (Index e = 0; e < n; ++e) f(e);
    return;
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (Index e = 0; e < n; ++e) f(e);
}

}  // namespace rpfem
