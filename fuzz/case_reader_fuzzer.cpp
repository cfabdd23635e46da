// libFuzzer target: a case file read as `rpfem run` reads it before its
// first step. Each input is written to a file and read with
// prepare_case (TOML, scene, monitors, [expect], [[variants]], contact,
// unknown keys); then the run is set up (reference motion, scales) and
// stopped before its first solve. Each of the case's variants is read the
// same way with its overrides, as `--variant NAME` does.
//
// InputError is the reader's answer to bad input (rpfem exits 2). Anything
// else is a finding: another exception (rpfem's "internal error", exit 1)
// is printed and aborts; a crash, a leak or undefined behaviour is
// reported by the sanitizers.
//
// The input is written into RPFEM_FUZZ_CASE_DIR (scripts/fuzz: a copy of
// cases/extremes, so that a reference_case such as
// "../paper_test2_die.toml" exists), else into a fresh temporary folder.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "app/case_setup.hpp"
#include "io/variants.hpp"
#include "mesh_size_guard.hpp"
#include "model/stepper.hpp"

namespace {

std::string input_path;

// Stops a run at the end of its set-up: on_start comes after every check
// the stepper makes before the first solve.
struct SetUpDone {};
struct StopAtStart : rpfem::StepObserver {
  void on_start(const rpfem::DerivedParameters&, const std::vector<std::string>&,
                const std::vector<std::string>&) override {
    throw SetUpDone{};
  }
  void on_step(const rpfem::StepRecord&) override {}
};

// One run of the case, from reading to its set-up. Bad input ends it.
void read_and_set_up(const std::vector<std::string>& overrides) {
  if (rpfem::fuzz::mesh_elements(input_path, overrides) > rpfem::fuzz::kMaxElements) return;
  try {
    rpfem::PreparedCase c = rpfem::prepare_case(input_path, overrides, "");
    rpfem::load_columns(c);
    c.file->used_json();
    StopAtStart observer;
    try {
      rpfem::run_scene(*c.scene, *c.contact, observer);
    } catch (const SetUpDone&) {
    }
  } catch (const rpfem::InputError&) {
  }
}

void read_case() {
  read_and_set_up({});
  std::vector<rpfem::Variant> variants;
  try {
    rpfem::CaseFile probe(input_path);
    variants = rpfem::read_variants(probe.root());
  } catch (const rpfem::InputError&) {
    return;
  }
  for (const auto& v : variants) read_and_set_up(v.set);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::filesystem::path dir;
  if (const char* d = std::getenv("RPFEM_FUZZ_CASE_DIR")) {
    dir = d;
  } else {
    std::string tmpl = (std::filesystem::temp_directory_path() / "rpfem-fuzz-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) {
      std::perror("fuzz_case_reader: mkdtemp");
      std::abort();
    }
    dir = tmpl;
  }
  input_path = (dir / ("fuzz-input-" + std::to_string(getpid()) + ".toml")).string();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  {
    std::ofstream out(input_path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) {
      std::perror(("fuzz_case_reader: writing " + input_path).c_str());
      std::abort();
    }
  }
  try {
    read_case();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_case_reader: %s escaped the reader (rpfem: internal error): %s\n",
                 typeid(e).name(), e.what());
    std::abort();
  }
  return 0;
}
