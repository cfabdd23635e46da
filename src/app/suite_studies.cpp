#include "app/suite_studies.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/case_folder.hpp"

namespace fs = std::filesystem;

namespace rpfem {

std::vector<SweepPlan> plan_studies(const SuiteOptions& opt) {
  const std::vector<fs::path> files = case_files(opt.cases_dir + "/studies", opt.studies, "study");
  std::vector<SweepPlan> plans;
  if (!opt.run_studies) return plans;
  auto named = [](const std::vector<std::string>& v, const std::string& x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  std::string left_out;
  for (const auto& path : files) {
    const std::string name = path.stem().string();
    SweepOptions s;
    s.study_file = path.string(), s.cases_dir = opt.cases_dir, s.out_dir = opt.out_dir + "/studies/" + name;
    s.quick = opt.quick, s.quiet = opt.quiet;  // its runs go to the suite's pool
    if (!opt.studies.empty()) {
      if (named(opt.studies, name)) plans.push_back(plan_sweep(s));
      continue;
    }
    // The study's scene from its file alone: a study left out is not planned.
    const std::string scene = fs::path(read_study(s.study_file, s.cases_dir, s.quick).case_file).stem().string();
    if (opt.scenes.empty() || named(opt.scenes, scene))
      plans.push_back(plan_sweep(s));
    else
      left_out += (left_out.empty() ? "" : ", ") + name + " (" + scene + ")";
  }
  if (!opt.quiet && !left_out.empty())
    std::printf("studies left out, their scenes not selected by --scene (--study NAME runs one): %s\n",
                left_out.c_str());
  return plans;
}

}  // namespace rpfem
