// The fuzz harness's bound on what a case may make the reader allocate:
// the elements its generated meshes would have. Division counts go up to
// 100000 per direction and run.mesh_factor up to 16, so a few bytes of
// input can ask for 1e10 elements; the harness skips such a case before
// meshing (an out-of-memory there is the input's size, not a bug).
#pragma once
#include <string>
#include <vector>

namespace rpfem::fuzz {

// Above this many elements in all, the harness does not read the case.
// The shipped cases have at most a few thousand.
constexpr double kMaxElements = 20000;

// The elements of every body's generated mesh, from its division counts
// times run.mesh_factor as the reader rounds them, after the overrides.
// Read leniently: a value the reader would refuse counts as one division,
// and a file that does not parse as zero (the reader then says why).
double mesh_elements(const std::string& case_file, const std::vector<std::string>& overrides);

}  // namespace rpfem::fuzz
