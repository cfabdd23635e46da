// Running a shipped case from an acceptance test: one output folder per test
// (ctest runs tests in parallel; suite and test name, as two suites may
// name a test alike), the exit code checked.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/types.hpp"
#include "material/flow_stress.hpp"
#include "results.hpp"

namespace rpfem::accept {

inline std::string test_out_dir(const std::string& suffix = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string out = (std::filesystem::temp_directory_path() /
                           ("rpfem_accept_" + std::string(info->test_suite_name()) + "." + info->name() + suffix))
                              .string();
  std::filesystem::remove_all(out);
  return out;
}

// Runs `rpfem ARGS` (ARGS quoted for the shell by the caller); with a log
// path its output goes there and, given `output`, is read back. The exit
// code, -1 if it did not exit normally.
inline int rpfem(const std::string& args, const std::string& log = "", std::string* output = nullptr) {
  const std::string cmd = std::string(RPFEM_BINARY) + " " + args + (log.empty() ? "" : " > " + log + " 2>&1");
  const int status = std::system(cmd.c_str());
  if (output) *output = read_text(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs cases/<name>.toml with extra options; expects exit code `rc`.
inline std::string run_case(const std::string& name, const std::string& extra = "", int rc = 0,
                            const std::string& suffix = "") {
  const std::string out = test_out_dir(suffix);
  const std::string args = "run " + std::string(RPFEM_SOURCE_DIR) + "/cases/" + name + ".toml --out " + out +
                           " --quiet " + extra;
  EXPECT_EQ(rpfem(args), rc) << args;
  return out;
}

// AISI 1035 as the upsetting cases state it (eps0 = 0.02; with the rate
// term m = 0.01, rate_ref = 0.1 1/s of the plane-strain case).
inline FlowStressLaw aisi1035(bool rate_sensitive = false) {
  FlowStressLaw l;
  l.K = 91.97 * kKgfPerMm2ToMPa;
  l.n = 0.17;
  l.eps0 = 0.02;
  if (rate_sensitive) {
    l.m = 0.01;
    l.rate_ref = 0.1;
  }
  return l;
}

}  // namespace rpfem::accept
