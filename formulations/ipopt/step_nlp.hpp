// One step's velocity field as Ipopt's nonlinear program (TNLP interface):
//   minimize Pi(u) + sum_j g_j s_j
//                     (the kernel's functional: StepProblem::energy, its
//                     gradient R(u) and its sparse consistent Hessian; the
//                     slacks s_j of exact friction, ipopt_step_solver.hpp,
//                     at their costs g_j)
//   subject to  a_j . (u, s) >= l_j   (linear rows: the gap at the end of
//                                 the step, over dt, per candidate pair;
//                                 s_j >= +-gamma_T,j for exact friction)
// The unknowns are x = (u, s), the slacks last. Exact first and second
// derivatives, sparse; the rows are constant and the slacks' cost linear,
// so the rows' Hessian is zero, the Lagrangian's is Pi's (in u alone), and
// Ipopt is told the Jacobian is constant.
// Ipopt's multiplier convention: grad Pi + A^T lambda = 0 with lambda <= 0
// for an active lower bound, so the row's force is -lambda (N).
#pragma once
#include <IpTNLP.hpp>

#include <string>
#include <utility>
#include <vector>

#include "core/types.hpp"
#include "model/step_problem.hpp"

namespace rpfem {

struct LinearRow {
  std::vector<std::pair<Index, double>> terms;  // (unknown of x = (u, s), coefficient)
  double lower = 0;                             // a . x >= lower
};

struct NlpOutcome {
  Ipopt::SolverReturn status = Ipopt::INTERNAL_ERROR;
  Vec u;                       // solution (reduced unknowns)
  Vec slack;                   // the slacks' values at the solution (mm/s)
  std::vector<double> lambda;  // row multipliers (Ipopt's sign: <= 0 pressing)
  int iterations = 0;
  // The objective's gradient R(u) at the solution and its element-force
  // scale (N), where Ipopt's last evaluation was there (else empty).
  Vec grad;
  double grad_scale = 0;
};

class StepNlp final : public Ipopt::TNLP {
 public:
  // force_scale (N) and speed_scale (mm/s) scale the objective's gradient
  // and the rows to order one (Ipopt's user scaling), so Ipopt's tol is
  // relative to the contact load.
  // start: x = (u, s), the slacks last, one per entry of slack_cost (N,
  // the slacks' costs g_j; read at every evaluation, so a re-solve takes
  // the costs as they are then).
  // start_lambda: the rows' multipliers to start from (Ipopt's warm start,
  // used when its warm_start_init_point option is set), or null.
  // secant_after_cut: the Hessian after an iteration whose line search cut
  // the step is the secant tangent (intermediate_callback, eval_h).
  StepNlp(StepProblem& problem, const std::vector<LinearRow>& rows, const std::vector<double>& slack_cost,
          const Vec& start, double force_scale, double speed_scale, bool secant_after_cut, NlpOutcome& out,
          const std::vector<double>* start_lambda = nullptr);
  // The next solve of the same program (Ipopt's ReOptimizeTNLP, which
  // keeps the program's structure and the linear solver's analysis) from
  // another start, its outcome into `out`.
  void restart(const Vec& start, const std::vector<double>* start_lambda, NlpOutcome& out) {
    start_ = start, start_lambda_ = start_lambda, out_ = &out, grad_valid_ = false, secant_next_ = false;
  }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Index nele_jac,
                  Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor, Ipopt::Index m,
              const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele_hess, Ipopt::Index* iRow,
              Ipopt::Index* jCol, Ipopt::Number* values) override;
  bool get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index n,
                              Ipopt::Number* x_scaling, bool& use_g_scaling, Ipopt::Index m,
                              Ipopt::Number* g_scaling) override;
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj_value,
                             Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu, Ipopt::Number d_norm,
                             Ipopt::Number regularization_size, Ipopt::Number alpha_du, Ipopt::Number alpha_pr,
                             Ipopt::Index ls_trials, const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index m,
                         const Ipopt::Number* g, const Ipopt::Number* lambda, Ipopt::Number obj_value,
                         const Ipopt::IpoptData* ip_data, Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  StepProblem& problem_;
  const std::vector<LinearRow>& rows_;
  const std::vector<double>& slack_cost_;
  Vec start_;
  Ipopt::Index n_u_ = 0;  // the velocities' unknowns (x's head)
  const std::vector<double>* start_lambda_ = nullptr;
  double force_scale_ = 1, speed_scale_ = 1;
  bool secant_after_cut_ = true;
  NlpOutcome* out_;
  std::vector<std::pair<Ipopt::Index, Ipopt::Index>> lower_;  // (row, col) of the Hessian's lower triangle
  Ipopt::Index jac_nnz_ = 0;
  // The velocities u of x (its head).
  Vec velocities(const Ipopt::Number* x) const { return Eigen::Map<const Vec>(x, n_u_); }
  // The slacks' cost sum_j g_j s_j at x.
  double slack_energy(const Ipopt::Number* x) const;
  // R(u) at the point of the last eval_f (one element pass gives
  // both: StepProblem::residual_energy), valid until Ipopt's new_x.
  Vec grad_, grad_x_;
  double grad_scale_ = 0;
  bool grad_valid_ = false;
  bool secant_next_ = false;  // the last iteration's line search cut its step
};

// Human-readable name of an Ipopt return status.
std::string ipopt_status_text(Ipopt::SolverReturn status);

}  // namespace rpfem
