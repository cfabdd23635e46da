#include "ipopt/mumps_analysis_reuse.hpp"

#include <dlfcn.h>
#include <dmumps_c.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <vector>

namespace rpfem {

namespace {

// The inputs of one analysis and what it returned (MUMPS 5.5 user guide,
// sec. 5: JOB = 1 reads N, NNZ (or NZ), IRN, JCN, ICNTL and CNTL).
struct Analysis {
  MUMPS_INT n = 0;
  std::int64_t nnz = 0;
  std::vector<MUMPS_INT> irn, jcn;
  MUMPS_INT icntl[60];
  DMUMPS_REAL cntl[15];
  MUMPS_INT info[80], infog[80];
  DMUMPS_REAL rinfo[40], rinfog[40];
};

struct ThreadState {
  std::map<const DMUMPS_STRUC_C*, Analysis> last;  // per MUMPS instance
  MumpsAnalysisCounts counts;
  bool reuse = true;
};

thread_local ThreadState state;

// NNZ (64-bit) where the caller set it, else the older NZ (Ipopt 3.11's).
std::int64_t nonzeros(const DMUMPS_STRUC_C* id) { return id->nnz > 0 ? id->nnz : id->nz; }

// An analysis of a centralized assembled matrix (ICNTL(5) = 0, ICNTL(18) =
// 0: IRN and JCN on the host, as Ipopt hands them) that reads the pattern
// alone (MUMPS 5.5 user guide, ICNTL(6), (8), (12)): no maximum transversal
// (ICNTL(6) = 0: it permutes by the values), no scaling (ICNTL(8) = 0) and
// no ordering on the transversal's compressed graph (ICNTL(12) = 0 or 1).
// Any other is analysed every time: an ordering from another matrix's
// values is a different factorization, and on the backward extrusion a
// much slower one (docs/decisions.md).
bool pattern_only(const DMUMPS_STRUC_C* id) {
  return id->icntl[4] == 0 && id->icntl[17] == 0 && id->irn && id->jcn && id->icntl[5] == 0 && id->icntl[7] == 0 &&
         (id->icntl[11] == 0 || id->icntl[11] == 1);
}

bool same_inputs(const Analysis& a, const DMUMPS_STRUC_C* id) {
  const std::int64_t nz = nonzeros(id);
  const std::size_t bytes = static_cast<std::size_t>(nz) * sizeof(MUMPS_INT);
  return a.n == id->n && a.nnz == nz && std::memcmp(a.icntl, id->icntl, sizeof a.icntl) == 0 &&
         std::memcmp(a.cntl, id->cntl, sizeof a.cntl) == 0 && std::memcmp(a.irn.data(), id->irn, bytes) == 0 &&
         std::memcmp(a.jcn.data(), id->jcn, bytes) == 0;
}

Analysis inputs_of(const DMUMPS_STRUC_C* id) {
  Analysis a;
  a.n = id->n;
  a.nnz = nonzeros(id);
  a.irn.assign(id->irn, id->irn + a.nnz);
  a.jcn.assign(id->jcn, id->jcn + a.nnz);
  std::memcpy(a.icntl, id->icntl, sizeof a.icntl);
  std::memcpy(a.cntl, id->cntl, sizeof a.cntl);
  return a;
}

using DmumpsC = void (*)(DMUMPS_STRUC_C*);

DmumpsC mumps_entry() {
  static const DmumpsC real = [] {
    auto* f = reinterpret_cast<DmumpsC>(dlsym(RTLD_NEXT, "dmumps_c"));
    if (!f) {
      std::fprintf(stderr, "rpfem: MUMPS's dmumps_c not found after the executable (%s)\n", dlerror());
      std::abort();
    }
    return f;
  }();
  return real;
}

}  // namespace

MumpsAnalysisCounts mumps_analysis_counts() { return state.counts; }

bool set_mumps_analysis_reuse(bool on) {
  const bool was = state.reuse;
  state.reuse = on;
  return was;
}

}  // namespace rpfem

// MUMPS's C interface (dmumps_c.h), interposed as described in the header.
extern "C" __attribute__((visibility("default"))) void dmumps_c(DMUMPS_STRUC_C* id) {
  using rpfem::state;
  const MUMPS_INT job = id->job;
  const bool pattern = job == 1 && rpfem::pattern_only(id);
  if (pattern && state.reuse) {
    const auto it = state.last.find(id);
    if (it != state.last.end() && rpfem::same_inputs(it->second, id)) {
      const rpfem::Analysis& a = it->second;
      std::memcpy(id->info, a.info, sizeof a.info);
      std::memcpy(id->infog, a.infog, sizeof a.infog);
      std::memcpy(id->rinfo, a.rinfo, sizeof a.rinfo);
      std::memcpy(id->rinfog, a.rinfog, sizeof a.rinfog);
      ++state.counts.reused;
      return;
    }
  }
  // An instance starting or ending, or analysing anew (JOB 1, 4, 6), drops
  // its record (its address may be a new instance's next).
  if (job == 1 || job == 4 || job == 6 || job == -1 || job == -2) state.last.erase(id);
  rpfem::Analysis a;
  if (pattern) a = rpfem::inputs_of(id);
  rpfem::mumps_entry()(id);
  if (job == 1) ++state.counts.analysed;
  if (!pattern || id->info[0] < 0) return;  // a failed analysis is never reused
  std::memcpy(a.info, id->info, sizeof a.info);
  std::memcpy(a.infog, id->infog, sizeof a.infog);
  std::memcpy(a.rinfo, id->rinfo, sizeof a.rinfo);
  std::memcpy(a.rinfog, id->rinfog, sizeof a.rinfog);
  state.last.emplace(id, std::move(a));
}
