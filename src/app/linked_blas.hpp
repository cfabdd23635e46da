// Which BLAS this process runs on: the results of a sparse factorization
// depend on its rounding (docs/decisions.md, "Linear algebra and the
// element loops": the ring's inner diameter at 60 % moves by tenths of a point
// between Debian's reference BLAS and OpenBLAS), and the library is chosen at
// load time (Debian's alternatives, LD_LIBRARY_PATH), not at build time.
// Recorded with every run's provenance.
#pragma once
#include <string>

namespace rpfem {

// The real path of the BLAS library mapped into this process
// (/proc/self/maps: the first file named lib*blas*), or "unknown".
std::string linked_blas();

// Sets the BLAS's thread count where the library has one to set
// (OpenBLAS: openblas_set_num_threads, found in the process at run time,
// since the library is chosen at load time); returns the count in effect:
// OpenBLAS's, or 1 for a BLAS without threads (Debian's reference BLAS).
// A count already in effect is not set again: OpenBLAS's setter starts its
// thread server where none runs (a forked child: OpenBLAS stops it before
// every fork), and its idle thread spins on sched_yield for about 0.1 s
// (its thread timeout), as long as a whole short run.
int set_blas_threads(int threads);

}  // namespace rpfem
