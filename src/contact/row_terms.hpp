// The terms a row adds to the step's functional, shared by every
// enforcement that adds terms (penalty, augmented Lagrangian; and the
// friction alone under direct and ipopt). With the relative velocity u,
// gamma_N = u . n and gamma_T = u . t of the row (contact/pair_kinematics.hpp):
//
// Normal (paper eq. 7-8) with the gap correction of the step and, for the
// augmented Lagrangian, the multiplier lambda (N, >= 0):
//   r = gamma_N + g_from / dt   (the predicted end-of-step gap over dt; without
//                                the correction r = gamma_N, exactly eq. 7)
//   N = max(0, lambda - beta r),  E_N = N^2 / (2 beta)        (one-sided)
//   N = -beta r,                  E_N = (beta / 2) r^2        (two-sided, eq. 7)
// so that dE_N / dr = -N: a node that would end the step inside its master
// is pushed back onto it, one that would separate carries no force (C1,
// convex). lambda = 0 is the paper's penalty; Uzawa's update lambda <- N
// makes it the augmented Lagrangian (Bertsekas 1982, sec. 2.1; Laursen 2002,
// sec. 5.3).
// Friction (paper eq. 11-12, the Chen-Kobayashi arctan law,
// material/friction_law.hpp): the potential B psi(gamma_T) with the bound
//   factor:  B = m k w
//   Coulomb: B = min(mu max(N, 0), k w)   (capped at the shear yield k of
//            the softer side: sticking)
// B either fixed within the solve (direct, ipopt: B from the last solve's
// normal force) or live, a function of gamma_N through N, which adds the
// unsymmetric block psi'(gamma_T) (c (x) t) (dB/dV)^T, dB/dV = -mu beta
// (c (x) n) (the consistent tangent); the term is then not a potential,
// and with B frozen at an iterate (merit_bound) its energy is the merit
// whose gradient there is the term's gradient.
#pragma once
#include <array>

#include "material/friction_law.hpp"
#include "contact/pair_kinematics.hpp"
#include "core/types.hpp"
#include "model/contact_formulation.hpp"

namespace rpfem {

struct RowLaw {
  bool normal = true;         // false: friction only, with the bound fixed_bound
  double beta = 0;            // N s/mm
  double lambda = 0;          // N, the augmented Lagrangian's multiplier
  double inv_dt = 0;          // 1/dt with the gap correction, else 0
  bool one_sided = false;     // only N > 0 (else the two-sided eq. 7)
  // One-sided, N = 0: still return 1e-12 beta dn dn^T in the Hessian (a
  // row in contact lifted by an iterate keeps a body held only by
  // contacts from floating in the Newton matrix; not the exact Hessian,
  // which slows Newton by about 1e-12 beta / (1e-12 beta + K) per
  // iteration in that row's direction: 1e-6 made Test I's Newton linear at
  // 0.924, docs/decisions.md, "The penalty parameter"). At N = 0 with r =
  // lambda / beta exactly (a node resting at zero gap at the start) the full
  // beta is used.
  bool keep_stiffness = false;
  FrictionLaw::Kind kind = FrictionLaw::Kind::None;
  double m = 0, mu = 0;
  double k_weight = 0;        // N: the sticking bound k w
  double a = 1;               // smoothing speed, mm/s
  double fixed_bound = -1;    // >= 0: B fixed (friction-only rows, or a frozen state)
  // >= 0: the bound in the energy only (the merit anchored at an iterate);
  // gradient and Hessian use the live bound.
  double merit_bound = -1;
};

// A row's term depends on the velocities V of its nodes only through
// gamma_N and gamma_T, whose gradients are dn = c (x) n and dt = c (x) t:
//   dE/dV   = dE_dn dn + dE_dt dt
//   d2E/dV2 = H_nn dn dn^T + H_tt dt dt^T + H_tn dt dn^T
// (H_tn: Coulomb's live bound, the unsymmetric block). expand() writes
// them out over the row's nodes.
struct RowTerm {
  double energy = 0;
  double dE_dn = 0, dE_dt = 0;       // N
  double H_nn = 0, H_tt = 0, H_tn = 0;  // N s/mm
  double normal_force = 0;           // N, > 0 pressing
  double bound = 0;                  // N, friction bound B
  double friction = 0;               // N, friction force on the slave along t
  double gamma_n = 0, gamma_t = 0;   // mm/s
};

// The term at the nodal velocities vel (all nodes; the row reads its own).
RowTerm row_term(const PairKinematics& p, const RowLaw& law, const std::vector<Vec2>& vel);

// The gradient (2k) and, if hess is not null, the Hessian (2k x 2k,
// column-major) over the row's nodes, V = (v_0, v_1, ...) stacked.
void expand(const PairKinematics& p, const RowTerm& t, double* grad, double* hess);

// Adds the row's term to a sink (its Hessian only if the sink needs it).
void add_row_term(TermSink& sink, const PairKinematics& p, const RowTerm& t);

// The bound of the law for a row in contact pressing with N (N) under the
// sticking bound kw (N); 0 for a row not in contact.
double friction_bound(const FrictionLaw& law, bool in_contact, double N, double kw);

// Continuation in the smoothing speed a for a run's first solve (from rest
// the arctan law with a small a is nearly non-smooth and Newton may not
// find the sliding directions): a starts at the larger of a and 0.1 of the
// speed scale and is divided by 10 per solve until it reaches its value.
class SmoothingContinuation {
 public:
  SmoothingContinuation() = default;
  // Over the friction laws of a scene's interfaces.
  void include(const FrictionLaw& law) {
    if (law.kind != FrictionLaw::Kind::None) factor_ = std::max(factor_, 0.1 / law.a_relative);
  }
  double factor() const { return factor_; }
  // One step of the continuation; true while a was still enlarged (solve again).
  bool relax() {
    if (factor_ <= 1) return false;
    factor_ = std::max(1.0, factor_ / 10);
    return true;
  }

 private:
  double factor_ = 1;
};

}  // namespace rpfem
