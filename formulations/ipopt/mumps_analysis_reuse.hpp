// MUMPS's analysis (JOB = 1: ordering and symbolic factorization) kept
// across the Ipopt solves of one program.
//
// Ipopt 3.11's MumpsSolverInterface::InitializeImpl clears its "have a
// symbolic factorization" flag at every OptimizeTNLP and ReOptimizeTNLP,
// warm_start_same_structure or not, so every friction pass of a step
// (ipopt_enforcement.hpp) had MUMPS analyse the same pattern again: 867
// analyses for 237 programs on Test II's die, 4.2 % of the run's perf
// samples (1.2 % with the reuse; docs/decisions.md). This file defines the C entry point dmumps_c in the
// executable, which the dynamic linker binds libipopt's calls to ahead of
// libdmumps_seq's (the executable comes first in the lookup scope). It
// forwards every call to MUMPS's own dmumps_c (dlsym RTLD_NEXT) except an
// analysis that reads the pattern alone and whose inputs equal those of the
// instance's last one: the same order n, nonzeros, row and column indices,
// ICNTL and CNTL. That analysis MUMPS still holds (an instance keeps it
// until the next JOB = 1 or its JOB = -2), and the call returns with the
// INFO/INFOG/RINFO/RINFOG of the analysis it stands for: the factorizations
// that follow are those of analysing again, to the bit (tests
// MumpsAnalysisReuse.*, Ipopt.ReusedMumpsAnalysesGiveTheSameBits).
//
// State is per thread: an Ipopt solve and its MUMPS instance live on the
// thread that runs the step.
#pragma once

namespace rpfem {

struct MumpsAnalysisCounts {
  long analysed = 0;  // analyses MUMPS ran
  long reused = 0;    // analyses answered by the instance's last one
};

// This thread's counts so far.
MumpsAnalysisCounts mumps_analysis_counts();

// Whether this thread's analyses may be reused (default on); returns the
// previous setting.
bool set_mumps_analysis_reuse(bool on);

}  // namespace rpfem
