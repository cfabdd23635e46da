// "ipopt": each step's velocity field as a constrained minimization solved
// by Ipopt (Waechter and Biegler 2006) through its TNLP interface
// (step_nlp.hpp): the bodies' rigid-plastic functional, exactly as the
// kernel assembles it, subject to one linear inequality per candidate
// contact pair: the gap at the end of the step, linearized in the
// velocities, must not be negative,
//   g_end / dt = gamma_N + g_from / dt >= 0        (pair_kinematics.hpp)
// The multipliers are the normal contact forces N = -lambda >= 0, and the
// solution meets the Kuhn-Tucker conditions of paper eq. 6 (gap >= 0,
// N >= 0, N gap = 0) to Ipopt's tolerance; after each solve the
// formulation checks them itself and reports the worst residual of each
// (kkt_* in history.csv):
//   primal: max(0, -g_end) / h      (penetration per element size)
//   dual:   max(0, -N) / F          (F the element-force scale of the step)
//   complementarity: max |N g_end / dt| / (F v_ref)
//   stationarity: |R(u) + A^T lambda| / F
//   round_off: |R(u + one ulp) - R(u)| / F, the floor stationarity can reach
// Candidates: every node of a die's contact side; between bodies, each node
// of the finer surface over a segment of the other (one pass, roles fixed
// at the start). The active set is Ipopt's business. Friction
// (friction_bounds.hpp): the arctan law's potential with its bound fixed in
// a solve, updated from the multipliers between solves (a fixed point over
// the kernel's contact passes) until it changes by less than
// `friction_tolerance` of the largest bound.
#pragma once
#include <IpIpoptApplication.hpp>

#include <string>
#include <vector>

#include "contact/pair_kinematics.hpp"
#include "contact/segment_search.hpp"
#include "ipopt/step_nlp.hpp"
#include "io/case_file.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"

namespace rpfem {

class IpoptContact final : public ContactFormulation {
 public:
  IpoptContact(const Scene& scene, CaseSection settings);
  std::string name() const override { return "ipopt"; }

  void begin_step(const StepView& v) override;
  void couplings(const StepView& v, std::vector<std::vector<Index>>& out) const override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override;
  std::optional<SolveOutcome> solve(const StepView& v, StepProblem& problem, Vec& u) override;
  StepCheck check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  void advance(const StepView& v, const std::vector<Vec2>& vel) override;
  std::optional<double> reference_speed(const std::string& name) const override;
  void contact_forces(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                      std::vector<Vec2>& out) const override;
  std::vector<std::string> load_names() const override;
  std::vector<Vec2> loads(const StepView& v, const std::vector<Vec2>& F) const override;
  void node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const override;
  std::vector<std::string> report_names() const override;
  std::vector<double> report() const override;
  std::vector<NamedValue> derived() const override;
  // At the end of the step (kkt_primal).
  std::optional<double> max_penetration_rel() const override { return kkt_.primal; }

  struct Options {
    double tol = 1e-10;               // Ipopt's tol
    double bound_relax_factor = 1e-10;
    int max_iter = 500;
    std::string mu_strategy = "monotone";
    std::string linear_solver = "mumps";
    int print_level = 0;
    double mu_init = 1e-6;
  };
  struct Kkt {
    double primal = 0, dual = 0, complementarity = 0, stationarity = 0;
    double round_off = 0;  // R's change under one-ulp changes of u, / F: stationarity's floor
  };
  struct Pair {
    PairKinematics kin;
    int iface = 0;
    double h = 0;           // mm, the interface's element size
    double weight = 0;      // mm^2, the slave node's contact area (for pressures)
    double force = 0;       // N, normal contact force (-lambda) of the last solve
    double end_gap = 0;     // mm, predicted gap at the end of the step
    double kw = 0;          // N, sticking bound: shear yield k times the area w
    double bound = 0;       // N, friction bound B of this solve
    double friction = 0;    // N, friction force on the slave along t, this solve
  };
  const std::vector<Pair>& pairs() const { return pairs_; }
  const Kkt& kkt() const { return kkt_; }

 private:
  struct Interface {
    std::string name;
    ContactSurface slave, master;  // master empty for a die
    int die = -1;
    double h = 0;
    FrictionLaw friction;
  };
  std::array<Vec2, 3> pair_forces(const Pair& p) const;
  // In contact after the last solve: at zero end gap (to kPressGap of the
  // element size) with a compressive force. An interior point leaves tiny
  // positive multipliers (about mu / slack) on rows far from contact; they
  // must not count as contact (a ring's free faces got die friction).
  bool pressing(const Pair& p) const { return p.force > 0 && p.end_gap < kPressGap * p.h; }
  static constexpr double kPressGap = 1e-6;
  // One Ipopt solve from `from`, its complementarity tolerance set from
  // the element-force scale `force` (N; 0 keeps the last).
  NlpOutcome optimize(StepProblem& problem, const std::vector<LinearRow>& rows, const Vec& from, double force);
  // The Kuhn-Tucker residuals of a solve into kkt_ and the pairs' forces and
  // gaps; returns the element-force scale at the solution.
  double measure(const StepView& v, const StepProblem& problem, const std::vector<LinearRow>& rows,
                 const std::vector<int>& row_pair, const NlpOutcome& out);
  // k w and the friction bound of every pair from per-node normal forces (N).
  void set_bounds(const StepView& v, const std::vector<double>& force);

  const Scene& scene_;
  Options opt_;
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;
  std::vector<Interface> ifaces_;
  std::vector<Pair> pairs_;
  double capture_ = 1, speed_scale_ = 0, sym_tol_ = 0, sigma_ref_ = 0;
  double area_ = 0;  // mm^2, all slave surfaces at the start (force scale)
  double round_off_force_ = 0;  // Newton's tol_force (relative residual)
  double last_scale_ = 0;       // N, the element-force scale of the last solve (Ipopt's complementarity tolerance)
  double friction_tol_ = 0, friction_change_ = 0;
  std::vector<double> last_force_;  // N per node: the last accepted solve's normal force (first bounds of a step)
  Kkt kkt_;
  int active_ = 0, rows_ = 0;
  double max_penetration_ = 0;  // mm (per element size: kkt_.primal)
};

}  // namespace rpfem
