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
    s.jobs = opt.jobs, s.quick = opt.quick, s.quiet = opt.quiet;
    if (!opt.studies.empty()) {
      if (named(opt.studies, name)) plans.push_back(plan_sweep(s));
      continue;
    }
    SweepPlan p = plan_sweep(s);
    const std::string scene = fs::path(p.study.case_file).stem().string();
    if (opt.scenes.empty() || named(opt.scenes, scene))
      plans.push_back(std::move(p));
    else
      left_out += (left_out.empty() ? "" : ", ") + name + " (" + scene + ")";
  }
  if (!opt.quiet && !left_out.empty())
    std::printf("studies left out, their scenes not selected by --scene (--study NAME runs one): %s\n",
                left_out.c_str());
  return plans;
}

}  // namespace rpfem
