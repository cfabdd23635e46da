// "penalty": the reference paper's method (Jang and Hwang 2002, eq. 3-12).
// Each contact interface of the scene ([[contact_pairs]]) is either a body
// against a rigid die (the die is the master) or a body against another
// body (node-to-segment, slave and master by Hallquist's rule, roles
// switching as the shapes change; or two-pass, each body slave to the other).
//   Search (contact/segment_search.hpp): bucket grid, then the signed area
//     of the triangle (master a, master b, slave) and the least-squares
//     master line of paper Fig. 3.
//   Normal: the penalty (beta/2) r^2 on the normal relative velocity of each
//     active pair, r = gamma_N + g0/dt (pair_terms.hpp); exact gradient and
//     Hessian (the geometry is fixed within the step).
//   beta = beta_hat w_s per pair, w_s the slave node's lumped contact area;
//     default beta_hat = 1e4 sigma_ref L / (v_ref h): ten thousand times the
//     stiffness of an element of size h at the reference strain rate
//     v_ref / L (sigma_ref the softer body's initial flow stress), so the end-of-
//     step penetration is about p dt / beta_hat = (stroke increment / L) h /
//     1e4 (p = sigma_ref). An instantaneous solve (no gap yet) lets the
//     bodies approach at p / beta_hat, 1e-4 of v_ref h / L: the two-pass
//     patch test's first solve is uniform to 4e-4 with it, 3.5e-3 with 1e3
//     (docs/notes.md); Newton's cost barely changes (Test II: +5 %).
//   Friction: Chen-Kobayashi arctan law on the relative tangential velocity,
//     Coulomb with its consistent (unsymmetric) tangent: UMFPACK.
//   Contact state: a slave node touching (gap <= touch tolerance) becomes
//     active; an active pair whose normal force turns tensile is released
//     and the step solved again. A free slave node that would reach its
//     master within a step shortens the step (limit_dt), as in `direct`.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "contact/segment_search.hpp"
#include "io/case_file.hpp"
#include "model/contact_formulation.hpp"
#include "model/scene.hpp"
#include "penalty/pair_terms.hpp"

namespace rpfem {

class PenaltyContact final : public ContactFormulation {
 public:
  PenaltyContact(const Scene& scene, CaseSection settings);
  std::string name() const override { return "penalty"; }

  void begin_step(const StepView& v) override;
  void couplings(const StepView& v, std::vector<std::vector<Index>>& out) const override;
  void add_terms(const StepView& v, const std::vector<Vec2>& vel, TermSink& sink) const override;
  TangentKind tangent() const override { return {!coulomb_, !coulomb_, coulomb_}; }
  void anchor_merit(const StepView& v, const std::vector<Vec2>& vel) override;
  StepCheck check(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F) override;
  std::optional<double> limit_dt(const StepView& v, const std::vector<Vec2>& vel) const override;
  std::optional<double> reference_speed(const std::string& name) const override;
  void contact_forces(const StepView& v, const std::vector<Vec2>& vel, const std::vector<Vec2>& F,
                      std::vector<Vec2>& out) const override;
  std::vector<std::string> load_names() const override;
  std::vector<Vec2> loads(const StepView& v, const std::vector<Vec2>& F) const override;
  void node_fields(const StepView& v, std::map<std::string, std::vector<double>>& out) const override;
  std::vector<std::string> report_names() const override;
  std::vector<double> report() const override;
  std::vector<NamedValue> derived() const override;
  std::optional<double> max_penetration_rel() const override { return max_penetration_rel_; }

  // One [[contact_pairs]] entry.
  struct Interface {
    std::string name;                   // "<body>-<die>" or "<body>-<with>"
    std::array<ContactSurface, 2> side; // side[1] empty for a die
    int die = -1;
    FrictionLaw friction;
    double beta_hat = 0;                // MPa s/mm
    double h = 0;                       // mm, mean slave edge length at the start
    double sigma_ref = 0;               // MPa
    int slave = 0;                      // one-pass: the slave side
    double switch_guard = 0;            // mm, the master penetration that made the last switch
    int switched_step = -1;             // the step of the last switch (at most one per step)
    std::array<std::vector<char>, 2> active;  // per side, per surface node
  };
  struct Pair {
    int iface = 0, side = 0, local = 0;  // slave: interface, side, index in its surface nodes
    PairKinematics kin;
    PairLaw law;
    double weight = 0;    // mm^2, slave node's contact area share
    double h = 0;         // mm, local element size
    int master_element = -1;  // the master segment's element (body master)
    bool changed = false;   // contact state changed in this solve's passes
    bool free = false;      // an instantaneous solve (StepView::moves false) and the node clear of its master
    double merit_bound = -1;  // N, Coulomb's bound frozen by anchor_merit
    PairResult res;       // at the last converged solve
  };
  const std::vector<Pair>& pairs() const { return pairs_; }
  const std::vector<Interface>& interfaces() const { return ifaces_; }

 private:
  // Candidate pairs of one slave side: for a body master from the side's
  // search hits, for a die from its projection.
  void collect_pairs(const StepView& v, int iface, int side, const std::vector<std::optional<SegmentHit>>& hits);
  // The contact state lives in the interface (it persists across steps).
  bool active(const Pair& p) const { return ifaces_[p.iface].active[p.side][p.local]; }
  void set_active(const Pair& p, bool on) { ifaces_[p.iface].active[p.side][p.local] = on; }
  // One-sided penalty on the predicted end-of-step gap (the default, with
  // the gap correction): every candidate pair carries its term.
  bool one_sided() const { return gap_correction_; }
  bool engaged(const Pair& p) const { return one_sided() ? !p.free : active(p); }
  StepCheck check_one_sided(const StepView& v, const std::vector<Vec2>& vel);
  void continue_smoothing(StepCheck& out);
  void set_laws(const StepView& v);
  PairResult evaluate(const Pair& p, const std::vector<Vec2>& vel, bool hess) const;
  // Force of pair p on each of its nodes (the contact force on the bodies).
  std::array<Vec2, 3> pair_forces(const Pair& p) const;

  const Scene& scene_;
  std::vector<Interface> ifaces_;
  std::vector<Pair> pairs_;
  std::vector<std::string> events_;
  bool two_pass_ = false, gap_correction_ = true, coulomb_ = false, any_bodies_ = false;
  double touch_tol_ = 0, release_tol_ = 0, switch_tol_ = 0, capture_ = 0, speed_scale_ = 0;
  double a_factor_ = 1;  // smoothing continuation at the first solve
  double max_penetration_ = 0, max_penetration_rel_ = 0, master_penetration_ = 0, sym_tol_ = 0;
  int active_pairs_ = 0, role_switches_ = 0;
};

}  // namespace rpfem
