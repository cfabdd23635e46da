#include "app/optimize_1d.hpp"

#include <exception>
#include <vector>

namespace rpfem {

namespace {

struct Callbacks {
  const std::function<double(double)>* f;
  const std::function<double(double)>* c;
  std::exception_ptr error;
};

// NLopt's C++ wrapper turns an exception into a bare failure code: keep it
// and stop the search instead.
double call(const std::function<double(double)>& fn, const std::vector<double>& x, Callbacks& cb) {
  try {
    return fn(x[0]);
  } catch (...) {
    cb.error = std::current_exception();
    throw nlopt::forced_stop();
  }
}

double objective(const std::vector<double>& x, std::vector<double>&, void* data) {
  auto& cb = *static_cast<Callbacks*>(data);
  return call(*cb.f, x, cb);
}

double constraint(const std::vector<double>& x, std::vector<double>&, void* data) {
  auto& cb = *static_cast<Callbacks*>(data);
  return call(*cb.c, x, cb);
}

}  // namespace

Optimum minimize_1d(const Search1D& s, const std::function<double(double)>& f,
                    const std::function<double(double)>& c) {
  nlopt::opt opt(s.algorithm, 1);
  Callbacks cb{&f, &c, nullptr};
  opt.set_lower_bounds(std::vector<double>{s.lo});
  opt.set_upper_bounds(std::vector<double>{s.hi});
  opt.set_min_objective(objective, &cb);
  if (c) opt.add_inequality_constraint(constraint, &cb, 0.0);
  opt.set_xtol_abs(s.xtol);
  opt.set_maxeval(s.max_evals);
  std::vector<double> x{s.x0};
  Optimum out;
  nlopt::result rc;
  try {
    double f = 0;
    rc = opt.optimize(x, f);
  } catch (const nlopt::forced_stop&) {
    if (cb.error) std::rethrow_exception(cb.error);
    rc = nlopt::FORCED_STOP;
  } catch (const nlopt::roundoff_limited&) {
    rc = nlopt::ROUNDOFF_LIMITED;  // x and f hold the best point found (NLopt: typically useful)
  }
  out.x = x[0];
  out.result = static_cast<int>(rc);
  out.result_name = nlopt_result_to_string(static_cast<nlopt_result>(rc));
  return out;
}

std::string algorithm_code(nlopt::algorithm a) { return nlopt_algorithm_to_string(static_cast<nlopt_algorithm>(a)); }
std::string algorithm_description(nlopt::algorithm a) { return nlopt_algorithm_name(static_cast<nlopt_algorithm>(a)); }

}  // namespace rpfem
