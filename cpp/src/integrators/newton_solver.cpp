#include "hovi/integrators/newton_solver.hpp"

#include <cmath>

namespace hovi {

const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::MaxIterations: return "max_iterations";
    case SolveStatus::LineSearchFailed: return "line_search_failed";
    case SolveStatus::SingularJacobian: return "singular_jacobian";
    case SolveStatus::NonFinite: return "non_finite";
  }
  return "unknown";
}

NewtonSolver::NewtonSolver(const Model& model, const Quadrature& quad)
    : del(model, quad), newton(model, quad), del_trial_(model, quad), del_factor_(model, quad), factor_(model, quad),
      r_(model.n(), quad.s),
      r_trial_(model.n(), quad.s), dq_(model.n(), quad.s), dbar_(model.n(), quad.s), q_trial_(model.n(), quad.s + 1),
      p_trial_(model.n()) {}

SolveInfo NewtonSolver::solve(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                              const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                              Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next) {
  const int s = quad.s;
  const double target = opt.tol * (1 + (p.size() ? p.cwiseAbs().maxCoeff() : 0.0));
  SolveInfo info;
  del_residual(model, quad, del, qc, p, u, dt, r_, p_next);
  info.residual_evaluations = 1;
  info.residual = r_.size() ? r_.cwiseAbs().maxCoeff() : 0.0;
  double norm2 = r_.norm();
  bool reuse = true;                // may the kept factorisation serve this iteration?
  double previous_dq_norm = INFINITY;  // the first reused step of a solve is always tried
  for (;;) {
    if (!std::isfinite(norm2) || !p_next.allFinite()) {
      info.status = SolveStatus::NonFinite;
      return info;
    }
    if (info.residual <= target) {
      info.status = SolveStatus::Converged;
      return info;
    }
    if (info.iterations >= opt.max_iterations) {
      info.status = SolveStatus::MaxIterations;
      return info;
    }
    // A fresh factorisation unless the kept one still serves (a simplified Newton step).
    const bool fresh = !(opt.reuse_jacobian && factor_valid_ && reuse);
    if (fresh) {
      factor_valid_ = false;
      if (!newton_factor(model, quad, del, factor_)) {
        info.status = SolveStatus::SingularJacobian;
        return info;
      }
      del_factor_.Sbar = del.Sbar;  // newton_solve reads the kinematics of the factorisation
      del_factor_.Sdot = del.Sdot;
      del_factor_.dt = del.dt;
      factor_valid_ = true;
      ++info.factorizations;
    }
    newton_solve(model, quad, del_factor_, factor_, r_, dq_);
    ++info.iterations;
    if (!dq_.allFinite()) {
      if (!fresh) {  // the kept Jacobian no longer fits: refactor here
        reuse = false;
        continue;
      }
      info.status = SolveStatus::NonFinite;
      return info;
    }
    // A Newton step below round-off of q: the residual is at its floor (tol was set below what
    // double precision can reach at this dt), so the iterate is as converged as it can be.
    if (dq_.cwiseAbs().maxCoeff() <= 1e-14 * (1 + qc.cwiseAbs().maxCoeff())) {
      info.status = SolveStatus::Converged;
      return info;
    }
    const double dq_norm = dq_.norm();
    if (!fresh && !(dq_norm <= 0.25 * previous_dq_norm)) {  // slow contraction: refactor
      reuse = false;
      continue;
    }
    double lambda = 1;
    bool accepted = false;
    for (int bt = 0; bt <= (opt.line_search ? opt.max_backtracks : 0); ++bt, lambda *= 0.5) {
      q_trial_.col(0) = qc.col(0);
      q_trial_.rightCols(s) = qc.rightCols(s) + lambda * dq_;
      del_residual(model, quad, del_trial_, q_trial_, p, u, dt, r_trial_, p_trial_);
      ++info.residual_evaluations;
      const double trial2 = r_trial_.norm();
      if (!opt.line_search) {
        accepted = true;
        break;
      }
      if (!std::isfinite(trial2) || !p_trial_.allFinite()) continue;
      if (trial2 <= (1 - 1e-4 * lambda) * norm2) {  // Armijo on ||r||
        accepted = true;
        break;
      }
      newton_solve(model, quad, del_factor_, factor_, r_trial_, dbar_);  // simplified correction
      if (dbar_.norm() <= (1 - 0.25 * lambda) * dq_norm) {              // natural monotonicity
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (!fresh) {  // a kept Jacobian may mislead the search: retry with a fresh one
        reuse = false;
        continue;
      }
      info.status = SolveStatus::LineSearchFailed;
      return info;
    }
    reuse = lambda == 1;  // after a damped step the Jacobian is refactored
    previous_dq_norm = dq_norm;
    std::swap(del, del_trial_);
    qc = q_trial_;
    r_.swap(r_trial_);
    p_next = p_trial_;
    norm2 = r_.norm();
    info.residual = r_.cwiseAbs().maxCoeff();
  }
}

}  // namespace hovi
