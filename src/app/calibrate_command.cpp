#include "app/calibrate_command.hpp"
#include "app/output_folder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/auto_beta.hpp"
#include "app/calibration_runs.hpp"
#include "app/case_setup.hpp"
#include "app/optimize_1d.hpp"
#include "core/types.hpp"
#include "curve_fit.hpp"

namespace fs = std::filesystem;

namespace rpfem {

namespace {

// The simulated curve a target is compared with: a history column against
// x = stroke * x_per_mm (stroke in mm, or the height reduction in %).
struct Comparison {
  std::string column;
  double x_per_mm = 1;
  double height = 0;  // mm (ring table)
  bool magnitude_kN = false;
};

Comparison comparison_for(const TargetCurve& target, const CalibrateOptions& opt, const PreparedCase& pc) {
  Comparison c;
  if (target.kind == TargetKind::LoadStroke) {
    c.column = opt.load_column.empty() ? pc.scene->stepping.reference + ".Fy" : opt.load_column;
    c.magnitude_kN = true;
    return c;
  }
  c.column = opt.monitor;
  const auto& m = pc.monitors;
  if (std::none_of(m.begin(), m.end(), [&](const Monitor& x) { return x.name == c.column; })) {
    std::string names;
    for (const auto& x : m) names += (names.empty() ? "" : ", ") + x.name;
    throw InputError(opt.case_file + ": --monitor '" + c.column + "': the case has no such [[monitors]] entry" +
                     (names.empty() ? std::string(" (it has none)") : "; it has: " + names));
  }
  if (opt.height) {
    c.height = *opt.height;
  } else {
    const auto& x = pc.scene->mesh.x;
    const auto [lo, hi] = std::minmax_element(x.begin(), x.end(), [](const Vec2& a, const Vec2& b) { return a(1) < b(1); });
    c.height = (*hi)(1) - (*lo)(1);
  }
  c.x_per_mm = 100 / c.height;
  return c;
}

double misfit_of(const TargetCurve& target, const Comparison& c, const History& h, const std::string& path,
                 const std::string& option) {
  if (!h.data.count(c.column)) {
    std::string names;
    for (const auto& n : h.columns) names += (names.empty() ? "" : ", ") + n;
    throw InputError(option + " '" + c.column + "': not a column of " + path + "; its columns: " + names);
  }
  std::vector<double> x = h.at("stroke"), y = h.at(c.column);
  for (double& v : x) v *= c.x_per_mm;
  if (c.magnitude_kN)
    for (double& v : y) v = std::abs(v) / 1e3;
  return target_misfit(target, x, y);
}

// The search's start: --x0, else the case's current value of --param if
// within --bounds, else their middle. The case must use the key as a
// number and accept both bounds (checked before any run).
double start_value(const CalibrateOptions& opt, const PreparedCase& pc, double lo, double hi) {
  const auto current = used_number(*pc.file, opt.param);
  if (!current)
    throw InputError(opt.case_file + ": --param '" + opt.param +
                     "': expected a number this case uses with these settings (a friction coefficient needs its "
                     "law, e.g. --set dies.top_die.friction.law=coulomb for mu)");
  for (double b : {lo, hi}) {  // the bounds must be values the case accepts
    auto o = opt.overrides;
    o.push_back(opt.param + "=" + exact_text(b));
    try {
      prepare_case(opt.case_file, o, opt.formulation);
    } catch (const InputError& e) {
      throw InputError("--bounds: " + exact_text(b) + ": " + e.what());
    }
  }
  const double x0 = opt.x0.value_or(*current >= lo && *current <= hi ? *current : (lo + hi) / 2);
  if (x0 < lo || x0 > hi) throw InputError("--x0 " + exact_text(x0) + ": expected a value within --bounds");
  return x0;
}

// The case's stroke must reach the target's last point.
void require_reach(const TargetCurve& target, const Comparison& cmp, const PreparedCase& pc) {
  const double end_stroke = pc.scene->stepping.end_stroke;
  require_within(target, end_stroke * cmp.x_per_mm,
                 "the case's stepping.end_stroke = " + exact_text(end_stroke) + " mm" +
                     (target.kind == TargetKind::Ring ? " (" + exact_text(end_stroke * cmp.x_per_mm) +
                                                            " % of the height " + exact_text(cmp.height) + " mm)"
                                                      : ""));
}

void print_fit_start(const CalibrateOptions& opt, const SearchRecord& s, const TargetCurve& target,
                     const Comparison& cmp, const std::string& unit) {
  const bool ring = target.kind == TargetKind::Ring;
  std::printf("rpfem calibrate: %s in [%g, %g] from %g by NLopt %s; target %s (%s, %zu points) against %s%s; "
              "misfit: RMS (%s); runs in %s/evals\n",
              opt.param.c_str(), s.lo, s.hi, s.x0, algorithm_code(s.algorithm).c_str(), opt.target.c_str(),
              ring ? "ring table" : "load-stroke table", target.x.size(), cmp.column.c_str(),
              cmp.magnitude_kN ? " (|N| / 1000)" : "", unit.c_str(), opt.out_dir.c_str());
}

void print_evaluation(const std::string& param, double x, const Evaluation& e, bool cached) {
  if (cached) std::printf("  (cached) %s = %-12.6g misfit %.4e\n", param.c_str(), x, e.score);
  else
    std::printf("  eval %3d: %s = %-12.6g misfit %.4e  run %.2f s  %s\n", e.index, param.c_str(), x, e.score,
                e.wall_s, e.dir.c_str());
  std::fflush(stdout);
}

// What calibration.json says of the target and the objective.
void record_target(CalibrationLog& log, const CalibrateOptions& opt, const TargetCurve& target, const Comparison& cmp) {
  const bool ring = target.kind == TargetKind::Ring;
  toml::table tgt{{"file", fs::absolute(opt.target).string()}, {"kind", ring ? "ring" : "load_stroke"},
                  {"points", static_cast<int64_t>(target.x.size())}, {"column", cmp.column}};
  if (ring) tgt.insert("height_mm", cmp.height);
  log.record().insert("target", tgt);
  log.record().insert("misfit_definition", misfit_definition(target.kind));
  log.record().insert("objective", "the misfit squared (the mean square: same minimizer, smooth at a perfect fit)");
}

int fit_curve(const CalibrateOptions& opt) {
  if (opt.param.empty()) throw InputError("--target needs --param KEY (the case key to identify)");
  if (opt.bounds.size() != 2 || !(opt.bounds[0] < opt.bounds[1]))
    throw InputError("--bounds: expected LO,HI with LO < HI (the range of " + opt.param + ")");
  const double lo = opt.bounds[0], hi = opt.bounds[1];
  const TargetCurve target = read_target_curve(opt.target);
  const PreparedCase pc = prepare_case(opt.case_file, opt.overrides, opt.formulation);
  const double x0 = start_value(opt, pc, lo, hi);
  const Comparison cmp = comparison_for(target, opt, pc);
  require_reach(target, cmp, pc);
  const bool ring = target.kind == TargetKind::Ring;

  SearchRecord s;
  s.mode = "fit", s.case_name = pc.scene->name, s.formulation = pc.contact->info().enforcement, s.key = opt.param;
  s.lo = lo, s.hi = hi, s.x0 = x0, s.xtol = opt.xtol.value_or(1e-4), s.algorithm = nlopt::LN_BOBYQA;
  s.run_overrides = {"stepping.end_stroke=" + exact_text(target.x.back() / cmp.x_per_mm)};
  if (!(s.xtol > 0)) throw InputError("--xtol: expected a positive number");
  RunSpec spec{opt.case_file, opt.formulation, opt.overrides, opt.param, opt.out_dir, opt.engine};
  spec.overrides.insert(spec.overrides.end(), s.run_overrides.begin(), s.run_overrides.end());
  const std::string option = ring ? "--monitor" : "--load";
  claim_output_folder(opt.out_dir, opt.force ? ExistingOutput::Replace : ExistingOutput::Refuse);
  CachedRuns runs(spec, [&](const History& h, const std::string& path) {
    return misfit_of(target, cmp, h, path, option);
  });
  const std::string unit = ring ? "percentage points" : "relative";

  if (!opt.quiet) print_fit_start(opt, s, target, cmp, unit);
  auto misfit = [&](double x) {
    bool cached = false;
    const Evaluation e = runs.evaluate(x, &cached);
    if (!opt.quiet) print_evaluation(opt.param, x, e, cached);
    return e.score;
  };

  CalibrationLog log(opt, s, runs, "misfit");
  record_target(log, opt, target, cmp);

  Optimum best;
  Evaluation at;
  try {
    misfit(x0);  // evaluation 1: the starting value (the cache serves NLopt's own call)
    best = minimize_1d({s.algorithm, lo, hi, x0, s.xtol, opt.max_evals}, [&](double x) {
      const double m = misfit(x);
      return m * m;
    });
    at = runs.evaluate(best.x);  // cached: NLopt's x is an evaluated point
  } catch (const RunFailed& e) {
    return log.stopped(e);
  }
  log.record().insert("result", toml::table{{"value", best.x},
                                            {"misfit", at.score},
                                            {"evaluation", at.index},
                                            {"nlopt_result", best.result},
                                            {"nlopt_result_name", best.result_name}});
  log.write("finished", best.x);
  if (!opt.quiet)
    std::printf("fitted %s = %.8g\nmisfit at the fit: %.4e (%s, RMS); at x0 = %g: %.4e\n", opt.param.c_str(), best.x,
                at.score, unit.c_str(), x0, runs.all().front().score);
  log.print_end(best.result, best.result_name);
  return 0;
}

}  // namespace

int calibrate_command(const CalibrateOptions& opt) {
  if (opt.max_evals < 1) throw InputError("--max-evals: expected a positive integer");
  if (opt.auto_beta) return auto_beta_command(opt);
  if (opt.target.empty()) throw InputError("calibrate: expected --target FILE with --param KEY, or --auto-beta TOL");
  return fit_curve(opt);
}

}  // namespace rpfem
