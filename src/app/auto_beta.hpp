// `rpfem calibrate CASE --auto-beta TOL`: the smallest penalty
// (formulations.penalty.beta_factor) whose run keeps the largest
// max_penetration_rel within TOL, searched in log10(beta_factor) by NLopt's
// COBYLA: minimize y = log10(beta_factor) subject to
// log10(penetration / TOL) <= 0. Penetration falls like 1 / beta, so the
// constraint is close to linear in y and COBYLA's linear models fit it.
// The answer is the smallest evaluated beta_factor that meets TOL; the run
// at the case's own beta_factor (the default) is evaluated first, for the
// time saved.
#pragma once
#include "app/calibrate_command.hpp"

namespace rpfem {

int auto_beta_command(const CalibrateOptions& opt);

}  // namespace rpfem
