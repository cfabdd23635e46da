// The contact and friction conditions of one row as nonlinear
// complementarity functions (NCP), and their generalized derivatives: what
// the semi-smooth Newton enforcement solves (ssn_step_solver.hpp).
//
// Unknowns of a row: the normal force lambda_N (N, > 0 pressing) and the
// friction force lambda_T (N, on the slave along t). Kinematics: the
// end-of-step gap over dt, r = gamma_N + g_from / dt (mm/s, >= 0 open;
// pair_kinematics.hpp), and the slip rate gamma_T (mm/s).
//
// Normal (Kuhn-Tucker: r >= 0, lambda_N >= 0, lambda_N r = 0), the `min`
// type (Alart and Curnier 1991; Hueber, Stadler and Wohlmuth 2008, eq. 2.5):
//   C_N = lambda_N - max(0, lambda_N - c_N r)
// active (lambda_N - c_N r > 0): C_N = c r, the row held at zero end gap;
// inactive: C_N = lambda_N.
// Friction with the bound g >= 0 (|lambda_T| <= g; gamma_T = 0 where
// |lambda_T| < g; lambda_T = -g sign(gamma_T) where slipping), as the
// projection onto [-g, g] (Alart and Curnier 1991, eq. 33; GetFEM's
// Alart-Curnier brick):
//   C_T = lambda_T - P_[-g, g](lambda_T - c_T gamma_T)
// stick (|lambda_T - c_T gamma_T| < g): C_T = c_T gamma_T;
// slip: C_T = lambda_T - g s, s = sign(lambda_T - c_T gamma_T).
// The bound: 0 on an inactive row; active,
//   friction factor (Tresca): g = m k w
//   Coulomb: g = min(mu (lambda_N - c_N r), k w)  (the augmented normal force,
//            Hueber et al. 2008, eq. 2.7; capped at the sticking bound)
// so that Coulomb's slip rows couple lambda_T to lambda_N and r.
// `min` rather than Fischer-Burmeister: piecewise linear, so a Newton step
// with the sets fixed meets the conditions exactly, and MOOSE measured it
// ahead (104 against 135 to 149 iterations, PR #13508).
// c_N, c_T (N s/mm) change the iteration's path, not the solution.
//
// Grazing: the friction factor's bound jumps from 0 to m k w as a row
// presses, so a row at the rim of the contact zone can have no solution on
// any branch (in contact, its friction lifts it off, lambda_N < 0; out of
// contact, it penetrates). Its solution is then on the jump: zero gap, no
// normal force, and a friction force within the bound, the law's convex
// hull at lambda_N = 0 (the set-valued friction law, Moreau 1988; Jean
// 1999). The grazing branch holds it there:
//   C_N = c_N r,  C_T = lambda_N
// (the friction force is then what equilibrium asks; the solver checks it
// lies within [-g, g] and opposes the slip).
#pragma once

namespace rpfem {

struct RowFriction {
  enum class Kind { None, Tresca, Coulomb };
  Kind kind = Kind::None;
  double bound = 0;  // N, Tresca: m k w
  double mu = 0;     // Coulomb coefficient
  double cap = 0;    // N, Coulomb's cap: the sticking bound k w
  // false: the row's slip rate is fixed by other rows (a node held by two
  // dies): where it would stick, its friction force is zero instead, as
  // the split of the node's reaction between the dies is not determined
  // (a valid sticking force: within the bound, at zero slip).
  bool may_stick = true;
};

struct RowNcp {
  double cn = 0, ct = 0;  // N
  // Generalized derivatives (an element of Clarke's Jacobian).
  double dcn_dr = 0, dcn_dln = 0;
  double dct_dr = 0, dct_ds = 0, dct_dln = 0, dct_dlt = 0;
  double g = 0;           // N, the friction bound at this iterate
  // The branch: which piece of each piecewise linear function holds.
  bool active = false;    // normal
  bool stick = false;     // |lambda_T - c_T gamma_T| < g
  bool capped = false;    // Coulomb's bound at its cap
  double sign = 0;        // slip: sign(lambda_T - c_T gamma_T)
  bool grazing = false;   // held on the grazing branch (the solver's choice only)
};

// At lambda_N, lambda_T (N), r, gamma_T (mm/s), c_N and c_T (N s/mm). With `branch`,
// the functions on that branch (smooth, linear): the line search's merit
// at a trial point keeps the iterate's branch (ssn_step_solver.hpp).
RowNcp row_ncp(double lambda_n, double lambda_t, double r, double gamma_t, double cn, double ct, const RowFriction& f,
               const RowNcp* branch = nullptr);

}  // namespace rpfem
