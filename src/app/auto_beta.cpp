#include "app/auto_beta.hpp"
#include "app/output_folder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/calibration_runs.hpp"
#include "app/case_setup.hpp"
#include "app/optimize_1d.hpp"
#include "core/types.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

const char* kKey = "formulations.penalty.beta_factor";
const char* kColumn = "max_penetration_rel";

double largest_penetration(const History& h, const std::string& path) {
  const auto& p = h.at(kColumn);  // the penalty formulation always writes it
  if (p.empty()) throw RunFailed(path + ": no steps");
  return *std::max_element(p.begin(), p.end());
}

// --bounds of beta_factor (default 1e-6 to 1e6), checked.
std::vector<double> beta_bounds(const CalibrateOptions& opt) {
  const std::vector<double> bounds = opt.bounds.empty() ? std::vector<double>{1e-6, 1e6} : opt.bounds;
  if (bounds.size() != 2 || !(bounds[0] > 0) || !(bounds[0] < bounds[1]))
    throw InputError("--bounds: expected LO,HI with 0 < LO < HI (beta_factor, times the default beta)");
  return bounds;
}

void print_search_start(const SearchRecord& s, double tol, const std::string& out_dir) {
  std::printf("rpfem calibrate --auto-beta %g: the smallest %s in [%g, %g] with max %s <= %g, by NLopt %s in "
              "log10; runs in %s/evals\n",
              tol, kKey, s.lo, s.hi, kColumn, tol, algorithm_code(s.algorithm).c_str(), out_dir.c_str());
}

// The smallest evaluated beta_factor whose penetration meets tol (null if none).
const Evaluation* smallest_meeting(const std::vector<Evaluation>& all, double tol) {
  const Evaluation* best = nullptr;
  for (const auto& e : all)
    if (e.score <= tol && (!best || e.value < best->value)) best = &e;
  return best;
}

// No value met the tolerance: recorded and said; exit code 3.
int no_feasible_value(CalibrationLog& log, const SearchRecord& s, double tol, const toml::table& nlopt_rc) {
  const std::string why = "no beta_factor in [" + exact_text(s.lo) + ", " + exact_text(s.hi) + "] gave max " +
                          kColumn + " <= " + exact_text(tol) + " (raise --bounds' upper end)";
  log.record().insert("reason", why);
  log.record().insert("result", nlopt_rc);
  log.write("no feasible value");
  std::fprintf(stderr, "rpfem calibrate: %s\n", why.c_str());
  return 3;
}

// The result against the default beta's run (the time saved), recorded and,
// unless quiet, printed.
void report_result(CalibrationLog& log, const CalibrateOptions& opt, double tol, const Evaluation& best,
                   const Evaluation& reference, const toml::table& nlopt_rc) {
  const double saved = reference.wall_s - best.wall_s;
  const double saved_pct = reference.wall_s > 0 ? 100 * saved / reference.wall_s : 0.0;
  toml::table result{{"beta_factor", best.value},
                     {kColumn, best.score},
                     {"evaluation", best.index},
                     {"wall_time_s", best.wall_s},
                     {"default_beta_factor", reference.value},
                     {"default_max_penetration_rel", reference.score},
                     {"default_wall_time_s", reference.wall_s},
                     {"time_saved_s", saved},
                     {"time_saved_percent", saved_pct}};
  for (auto&& [k, v] : nlopt_rc) result.insert(k, v);
  log.record().insert("result", result);
  log.write("finished", best.value);
  if (!opt.quiet) {
    std::printf("smallest beta_factor with max %s <= %g: %.6g (penetration %.4e, run %.2f s)\n", kColumn, tol,
                best.value, best.score, best.wall_s);
    std::printf("default beta_factor %g: penetration %.4e, run %.2f s; time saved %.2f s (%.1f %%)\n", reference.value,
                reference.score, reference.wall_s, saved, saved_pct);
  }
}

}  // namespace

int auto_beta_command(const CalibrateOptions& opt) {
  const double tol = *opt.auto_beta;
  if (!(tol > 0)) throw InputError("--auto-beta: expected a positive tolerance on max_penetration_rel");
  if (!opt.formulation.empty() && opt.formulation != "penalty")
    throw InputError("--auto-beta searches the penalty formulation's beta: expected --formulation penalty or none, "
                     "got '" + opt.formulation + "'");
  const std::vector<double> bounds = beta_bounds(opt);
  const PreparedCase pc = prepare_case(opt.case_file, opt.overrides, "penalty");
  if (used_number(*pc.file, "formulations.penalty.beta"))
    throw InputError(opt.case_file + ": key 'formulations.penalty.beta': --auto-beta searches " + kKey +
                     ", which an absolute beta replaces; remove it");
  const double default_factor = used_number(*pc.file, kKey).value_or(1.0);
  const double x0 = opt.x0.value_or(default_factor);
  if (!(x0 >= bounds[0] && x0 <= bounds[1]))
    throw InputError("--x0 " + exact_text(x0) + ": expected a beta_factor within --bounds");

  SearchRecord s;
  s.mode = "auto_beta", s.case_name = pc.scene->name, s.formulation = "penalty", s.key = kKey;
  s.lo = bounds[0], s.hi = bounds[1], s.x0 = x0, s.xtol = opt.xtol.value_or(0.01), s.algorithm = nlopt::LN_COBYLA;
  if (!(s.xtol > 0)) throw InputError("--xtol: expected a positive number (decades of beta_factor)");
  claim_output_folder(opt.out_dir, opt.force ? ExistingOutput::Replace : ExistingOutput::Refuse);
  CachedRuns runs({opt.case_file, "penalty", opt.overrides, kKey, opt.out_dir, opt.engine}, largest_penetration);

  if (!opt.quiet) print_search_start(s, tol, opt.out_dir);
  auto penetration = [&](double factor) {
    bool cached = false;
    const Evaluation e = runs.evaluate(factor, &cached);
    if (!opt.quiet && !cached) {
      std::printf("  eval %3d: beta_factor = %-12.6g %s %.4e (%s)  run %.2f s  %s\n", e.index, factor, kColumn,
                  e.score, e.score <= tol ? "meets TOL" : "above TOL", e.wall_s, e.dir.c_str());
      std::fflush(stdout);
    }
    return e.score;
  };

  CalibrationLog log(opt, s, runs, kColumn);
  log.record().insert("tolerance", tol);
  log.record().insert("objective", std::string("minimize log10(beta_factor) subject to log10(max ") + kColumn +
                                       " / tolerance) <= 0; the result is the smallest evaluated beta_factor meeting it");

  Optimum opt_y;
  Evaluation reference;
  try {
    penetration(default_factor);  // evaluation 1: the default beta, for the time saved
    reference = runs.all().front();
    penetration(x0);
    const double floor = tol * 1e-12;  // a run without any penetration: far inside
    opt_y = minimize_1d({s.algorithm, std::log10(s.lo), std::log10(s.hi), std::log10(x0), s.xtol, opt.max_evals},
                        [](double y) { return y; },
                        [&](double y) { return std::log10(std::max(penetration(std::pow(10.0, y)), floor) / tol); });
  } catch (const RunFailed& e) {
    return log.stopped(e);
  }
  const toml::table nlopt_rc{{"nlopt_result", opt_y.result}, {"nlopt_result_name", opt_y.result_name}};
  const Evaluation* best = smallest_meeting(runs.all(), tol);
  if (!best) return no_feasible_value(log, s, tol, nlopt_rc);
  report_result(log, opt, tol, *best, reference, nlopt_rc);
  log.print_end(opt_y.result, opt_y.result_name);
  return 0;
}

}  // namespace rpfem
