// Libraries' OpenMP regions run inline on the calling thread.
//
// Debian's CHOLMOD (SuiteSparse 5.12) opens an OpenMP parallel region for
// each of its small clearing and copying loops, supernode by supernode.
// Held to one thread (on_one_thread below: a host teams region with
// thread_limit(1)), each region still starts and ends a team of one, and
// libgomp ends every team at a barrier that wakes its waiters with a futex
// system call, whether or not anyone waits: 1.14 million calls in 2 mm of
// the backward extrusion, about a tenth of its run time (docs/decisions.md,
// "Linear algebra and the element loops").
//
// The program therefore defines GOMP_parallel, libgomp's entry point for a
// `#pragma omp parallel` (GCC's ABI, GOMP_4.0), and exports it, so that
// the dynamic linker binds the libraries' calls to it before libgomp's.
// Inside an InlineOpenMP scope on this thread it calls the region's body
// directly, as the one thread of the team: a combined `parallel for`'s
// body then runs the whole loop (omp_get_num_threads() is 1 outside a
// region, omp_get_thread_num() 0), which is what a team of one computes.
// Everywhere else it hands the region to libgomp unchanged.
#pragma once
#include <cstdint>

namespace rpfem {

// While one lives, OpenMP regions opened on this thread run inline.
class InlineOpenMP {
 public:
  InlineOpenMP();
  ~InlineOpenMP();
  InlineOpenMP(const InlineOpenMP&) = delete;
  InlineOpenMP& operator=(const InlineOpenMP&) = delete;

 private:
  bool outer_;
};

// Parallel regions run inline so far, over all threads: whether the
// libraries' calls reach this program's GOMP_parallel (tests).
std::uint64_t inline_openmp_regions();

// Runs f with every OpenMP region a library opens on one thread, inline.
// Debian's CHOLMOD (SuiteSparse 5.12) opens its supernodal loops with a
// fixed CHOLMOD_OMP_NUM_THREADS = 4 threads; no arithmetic is split among
// them, so the factor does not depend on their number, but on a 2-core
// machine their barriers cost as much as the factorization itself (bench
// BM_CholmodSupernodalFourThreads against BM_CholmodSupernodal). Inside a
// host teams region of one team limited to one thread (OpenMP 5.0, 2.7
// teams construct: thread_limit) every region gets one thread, and within
// the InlineOpenMP scope it runs without the team libgomp would start and
// end for it. The kernel's own element loops run outside, on their
// threads.
template <class F>
void on_one_thread(F&& f) {
#ifdef _OPENMP
#pragma omp teams num_teams(1) thread_limit(1)
#endif
  {
    const InlineOpenMP inline_regions;
    f();
  }
}

}  // namespace rpfem
