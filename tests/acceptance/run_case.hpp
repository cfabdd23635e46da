// Running a shipped case from an acceptance test: one output folder per test
// (ctest runs tests in parallel), the exit code checked.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace rpfem::accept {

inline std::string test_out_dir(const std::string& suffix = "") {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string out = (std::filesystem::temp_directory_path() /
                           ("rpfem_accept_" + std::string(info->name()) + suffix))
                              .string();
  std::filesystem::remove_all(out);
  return out;
}

// Runs cases/<name>.toml with extra options; expects exit code `rc`.
inline std::string run_case(const std::string& name, const std::string& extra = "", int rc = 0,
                            const std::string& suffix = "") {
  const std::string out = test_out_dir(suffix);
  const std::string cmd = std::string(RPFEM_BINARY) + " run " + RPFEM_SOURCE_DIR + "/cases/" + name +
                          ".toml --out " + out + " --quiet " + extra;
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == rc) << cmd;
  return out;
}

}  // namespace rpfem::accept
