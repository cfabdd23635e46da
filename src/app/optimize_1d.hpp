// One bounded parameter searched by an NLopt derivative-free local method
// (`rpfem calibrate`). An exception thrown by the objective or constraint
// (a failed run, bad input found late) stops NLopt and is rethrown here.
#pragma once
#include <functional>
#include <string>

#include <nlopt.hpp>

namespace rpfem {

struct Search1D {
  nlopt::algorithm algorithm = nlopt::LN_BOBYQA;
  double lo = 0, hi = 1, x0 = 0;
  double xtol = 1e-4;  // absolute, on x
  int max_evals = 50;
};

struct Optimum {
  double x = 0;
  int result = 0;           // NLopt's return code (> 0 success)
  std::string result_name;  // e.g. XTOL_REACHED
};

// Minimizes f on [lo, hi] from x0; with a constraint c, subject to c(x) <= 0
// (the algorithm must accept inequality constraints, e.g. LN_COBYLA).
Optimum minimize_1d(const Search1D& s, const std::function<double(double)>& f,
                    const std::function<double(double)>& constraint = {});

// "LN_BOBYQA" and NLopt's description of the algorithm.
std::string algorithm_code(nlopt::algorithm a);
std::string algorithm_description(nlopt::algorithm a);

}  // namespace rpfem
