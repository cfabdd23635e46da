#include "ipopt/step_nlp.hpp"

#include <IpIpoptData.hpp>

#include <cmath>

namespace rpfem {

StepNlp::StepNlp(StepProblem& problem, const std::vector<LinearRow>& rows, const std::vector<double>& slack_cost,
                 const Vec& start, double force_scale, double speed_scale, bool secant_after_cut, NlpOutcome& out,
                 const std::vector<double>* start_lambda)
    : problem_(problem), rows_(rows), slack_cost_(slack_cost), start_(start),
      n_u_(static_cast<Ipopt::Index>(start.size() - slack_cost.size())), start_lambda_(start_lambda),
      force_scale_(force_scale), speed_scale_(speed_scale), secant_after_cut_(secant_after_cut), out_(&out) {
  // The Hessian's pattern is the kernel's (fixed within the step): read
  // from the assembler, not assembled (Ipopt's first Hessian is at the
  // start, from the element pass of its first objective).
  const SpMat& K = problem_.tangent_pattern();
  for (Eigen::Index c = 0; c < K.outerSize(); ++c)
    for (SpMat::InnerIterator it(K, c); it; ++it)
      if (it.row() >= it.col()) lower_.emplace_back(static_cast<Ipopt::Index>(it.row()), static_cast<Ipopt::Index>(it.col()));
  for (const auto& r : rows_) jac_nnz_ += static_cast<Ipopt::Index>(r.terms.size());
}

double StepNlp::slack_energy(const Ipopt::Number* x) const {
  double e = 0;
  for (std::size_t j = 0; j < slack_cost_.size(); ++j) e += slack_cost_[j] * x[n_u_ + static_cast<Ipopt::Index>(j)];
  return e;
}

bool StepNlp::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                           IndexStyleEnum& index_style) {
  n = static_cast<Ipopt::Index>(start_.size());
  m = static_cast<Ipopt::Index>(rows_.size());
  nnz_jac_g = jac_nnz_;
  nnz_h_lag = static_cast<Ipopt::Index>(lower_.size());
  index_style = C_STYLE;
  return true;
}

bool StepNlp::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                              Ipopt::Number* g_l, Ipopt::Number* g_u) {
  for (Ipopt::Index i = 0; i < n; ++i) x_l[i] = -2e19, x_u[i] = 2e19;  // Ipopt's "no bound"
  for (Ipopt::Index j = 0; j < m; ++j) g_l[j] = rows_[j].lower, g_u[j] = 2e19;
  return true;
}

bool StepNlp::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                                 Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) {
  if (init_x)
    for (Ipopt::Index i = 0; i < n; ++i) x[i] = start_[i];
  if (init_z)  // the unknowns have no bounds: their multipliers are unused
    for (Ipopt::Index i = 0; i < n; ++i) z_L[i] = 0, z_U[i] = 0;
  if (init_lambda) {
    if (!start_lambda_ || static_cast<Ipopt::Index>(start_lambda_->size()) != m) return false;
    for (Ipopt::Index j = 0; j < m; ++j) lambda[j] = (*start_lambda_)[j];
  }
  return true;
}

bool StepNlp::eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& obj_value) {
  // Ipopt asks for the gradient at the points it accepts, which it has
  // evaluated f at: both from one element pass (the same bits as the two
  // calls, test Conformance.ResidualAndEnergyInOnePassAreTheTwoCallsBits).
  (void)n;
  grad_x_ = velocities(x);
  // The same element pass keeps the consistent tangent's element terms:
  // an accepted trial is where Ipopt asks for the Hessian next.
  problem_.keep_tangent_terms(true);
  obj_value = problem_.residual_energy(grad_x_, grad_, grad_scale_) + slack_energy(x);
  problem_.keep_tangent_terms(false);
  grad_valid_ = true;
  return std::isfinite(obj_value);
}

bool StepNlp::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) {
  if (new_x || !grad_valid_) {
    grad_x_ = velocities(x);
    problem_.residual(grad_x_, grad_, grad_scale_);  // R = dPi/du
    grad_valid_ = true;
  }
  for (Ipopt::Index i = 0; i < n_u_; ++i) grad_f[i] = grad_[i];
  for (Ipopt::Index i = n_u_; i < n; ++i) grad_f[i] = slack_cost_[i - n_u_];  // d(g_j s_j)/ds_j
  return grad_.allFinite();
}

bool StepNlp::eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) {
  (void)n;
  if (new_x) grad_valid_ = false;
  for (Ipopt::Index j = 0; j < m; ++j) {
    double s = 0;
    for (const auto& [dof, a] : rows_[j].terms) s += a * x[dof];
    g[j] = s;
  }
  return true;
}

bool StepNlp::eval_jac_g(Ipopt::Index, const Ipopt::Number*, bool new_x, Ipopt::Index m, Ipopt::Index,
                         Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) {
  if (new_x) grad_valid_ = false;
  Ipopt::Index k = 0;
  for (Ipopt::Index j = 0; j < m; ++j)
    for (const auto& [dof, a] : rows_[j].terms) {
      if (values) {
        values[k] = a;
      } else {
        iRow[k] = j;
        jCol[k] = static_cast<Ipopt::Index>(dof);
      }
      ++k;
    }
  return true;
}

bool StepNlp::eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor, Ipopt::Index,
                     const Ipopt::Number*, bool, Ipopt::Index nele_hess, Ipopt::Index* iRow, Ipopt::Index* jCol,
                     Ipopt::Number* values) {
  if (new_x) grad_valid_ = false;
  if (!values) {
    for (Ipopt::Index k = 0; k < nele_hess; ++k) iRow[k] = lower_[k].first, jCol[k] = lower_[k].second;
    return true;
  }
  // The rows and the slacks' cost are linear: the Lagrangian's Hessian is
  // obj_factor K in u (none in the slacks), K the consistent tangent, or
  // the secant one after an iteration whose line search cut the step
  // (secant_after_cut, as Newton's: solver/newton.hpp).
  (void)n;
  const SpMat& K = problem_.tangent(velocities(x), !secant_next_);
  Ipopt::Index k = 0;
  for (Eigen::Index c = 0; c < K.outerSize(); ++c)
    for (SpMat::InnerIterator it(K, c); it; ++it)
      if (it.row() >= it.col()) {
        if (k >= nele_hess) return false;  // the pattern changed: cannot happen within a step
        values[k++] = obj_factor * it.value();
      }
  return k == nele_hess;
}

bool StepNlp::intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index iter, Ipopt::Number, Ipopt::Number,
                                    Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                                    Ipopt::Number alpha_pr, Ipopt::Index, const Ipopt::IpoptData*,
                                    Ipopt::IpoptCalculatedQuantities*) {
  // The consistent tangent of a rigid-plastic functional is nearly
  // singular along the plastic flow, and far from the solution its steps
  // overshoot: where Ipopt's line search cut the last step, the next
  // Hessian is the secant tangent (positive definite; a quasi-Newton step
  // for Ipopt). The backward extrusion: 12917 -> 5677 Ipopt iterations,
  // its warm starts no longer lost in line searches (docs/decisions.md).
  secant_next_ = secant_after_cut_ && iter > 0 && alpha_pr < 1;
  return true;
}

bool StepNlp::get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index,
                                     Ipopt::Number*, bool& use_g_scaling, Ipopt::Index m, Ipopt::Number* g_scaling) {
  // Pi has units N mm/s and its gradient N: over force_scale it is of order
  // one per unit speed; the rows (mm/s) over speed_scale are of order one.
  obj_scaling = 1.0 / force_scale_;
  use_x_scaling = false;
  use_g_scaling = true;
  for (Ipopt::Index j = 0; j < m; ++j) g_scaling[j] = 1.0 / speed_scale_;
  return true;
}

void StepNlp::finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                                const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index m, const Ipopt::Number*,
                                const Ipopt::Number* lambda, Ipopt::Number, const Ipopt::IpoptData* ip_data,
                                Ipopt::IpoptCalculatedQuantities*) {
  out_->status = status;
  out_->u = velocities(x);
  out_->slack = Eigen::Map<const Vec>(x + n_u_, n - n_u_);
  out_->lambda.assign(lambda, lambda + m);
  out_->iterations = ip_data ? ip_data->iter_count() : 0;
  out_->grad.resize(0);
  if (grad_valid_ && grad_x_ == out_->u) out_->grad = grad_, out_->grad_scale = grad_scale_;
}

std::string ipopt_status_text(Ipopt::SolverReturn s) {
  switch (s) {
    case Ipopt::SUCCESS: return "solved";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT: return "solved to the acceptable level only";
    case Ipopt::MAXITER_EXCEEDED: return "maximum number of iterations exceeded";
    case Ipopt::CPUTIME_EXCEEDED: return "CPU time limit exceeded";
    case Ipopt::STOP_AT_TINY_STEP: return "search direction too small (stopped at a tiny step)";
    case Ipopt::LOCAL_INFEASIBILITY: return "converged to a point of local infeasibility (the contact constraints cannot all be met)";
    case Ipopt::RESTORATION_FAILURE: return "restoration phase failed";
    case Ipopt::DIVERGING_ITERATES: return "iterates diverging";
    case Ipopt::ERROR_IN_STEP_COMPUTATION: return "error in the step computation";
    case Ipopt::INVALID_NUMBER_DETECTED: return "invalid number in a function or derivative";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM: return "too few degrees of freedom";
    case Ipopt::INVALID_OPTION: return "invalid option";
    case Ipopt::OUT_OF_MEMORY: return "out of memory";
    case Ipopt::USER_REQUESTED_STOP: return "stopped by the user callback";
    case Ipopt::FEASIBLE_POINT_FOUND: return "feasible point found";
    case Ipopt::INTERNAL_ERROR: return "internal error";
    case Ipopt::UNASSIGNED: break;
  }
  return "unknown status";
}

}  // namespace rpfem
