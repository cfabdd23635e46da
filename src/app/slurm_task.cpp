#include "app/slurm_task.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "core/types.hpp"
#include "io/result_writer.hpp"

namespace rpfem {

namespace {

std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '\t' ? "\\t" : c == '\n' ? "\\n" : c == '\\' ? "\\\\" : std::string(1, c);
  return out;
}

// A line's fields, unescaped.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out(1);
  for (std::size_t k = 0; k < line.size(); ++k) {
    if (line[k] == '\t') {
      out.emplace_back();
    } else if (line[k] == '\\' && k + 1 < line.size()) {
      const char c = line[++k];
      out.back() += c == 't' ? '\t' : c == 'n' ? '\n' : c;
    } else {
      out.back() += line[k];
    }
  }
  return out;
}

}  // namespace

void write_task_runs(const std::string& path, const std::vector<PoolRun>& runs) {
  std::ofstream out(path, std::ios::trunc);
  for (const PoolRun& r : runs) {
    out << escaped(r.dir) << '\t' << escaped(r.case_file) << '\t' << escaped(r.formulation) << '\t'
        << escaped(r.variant);
    for (const auto& o : r.overrides) out << '\t' << escaped(o);
    out << '\n';
  }
  if (!out) throw InputError("--engine slurm: cannot write " + path);
}

std::vector<PoolRun> read_task_runs(const std::string& path, std::size_t first, std::size_t count) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path + " (the Slurm engine's list of runs)");
  std::vector<PoolRun> runs;
  std::string line;
  for (std::size_t n = 1; n < first + count && std::getline(in, line); ++n) {
    if (n < first) continue;
    const auto f = fields(line);
    if (f.size() < 4) throw InputError(path + ": line " + std::to_string(n) + ": expected a folder, case file, "
                                       "formulation and variant separated by tabs");
    PoolRun r;
    r.label = r.dir = f[0];
    r.case_file = f[1], r.formulation = f[2], r.variant = f[3];
    r.overrides.assign(f.begin() + 4, f.end());
    runs.push_back(r);
  }
  return runs;
}

int slurm_task_command(const std::string& runs_file, std::size_t first, std::size_t count) {
  std::vector<PoolRun> runs = read_task_runs(runs_file, first, count);
  int status = 0;
  run_in_turn(runs, [&](std::size_t i) {
    const PoolRun& r = runs[i];
    char line[64];
    std::snprintf(line, sizeof line, "%d %.6f\n", r.rc, r.seconds);
    int rc = r.rc;
    try {
      write_text_atomically(r.dir + "/exit_code", line);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "rpfem: error: run %s: %s\n", r.dir.c_str(), e.what());
      rc = 90;
    }
    if (status == 0) status = rc;
  });
  return status;
}

}  // namespace rpfem
