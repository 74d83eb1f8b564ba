#include "hovi/integrators/newton_solver.hpp"

#include <algorithm>
#include <cmath>

#include "hovi/integrators/dense_direction.hpp"

namespace hovi {

const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::MaxIterations: return "max_iterations";
    case SolveStatus::LineSearchFailed: return "line_search_failed";
    case SolveStatus::SingularJacobian: return "singular_jacobian";
    case SolveStatus::NonFinite: return "non_finite";
    case SolveStatus::ContinuationStalled: return "continuation_stalled";
  }
  return "unknown";
}

NewtonSolver::NewtonSolver(const Model& model, const Quadrature& quad)
    : del(model, quad), newton(model, quad), del_trial_(model, quad), del_factor_(model, quad), factor_(model, quad),
      r_(model.n(), quad.s),
      r_trial_(model.n(), quad.s), dq_(model.n(), quad.s), dbar_(model.n(), quad.s), q_trial_(model.n(), quad.s + 1),
      p_trial_(model.n()) {}

NewtonSolver::~NewtonSolver() = default;

bool NewtonSolver::factor(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                          const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt) {
  factor_valid_ = false;
  factor_dense_ = uses_dense_direction(opt.direction, model, quad.s);
  if (factor_dense_) {
    if (!dense_) dense_ = std::make_unique<DenseDirection>(model, quad);
    if (!dense_->factor(model, quad, qc, u, dt, &del)) return false;  // del holds Algorithm 1 at qc
  } else {
    if (!newton_factor(model, quad, del, factor_)) return false;
    del_factor_.Sbar = del.Sbar;  // newton_solve reads the kinematics of the factorisation
    del_factor_.Sdot = del.Sdot;
    del_factor_.dt = del.dt;
  }
  factor_valid_ = true;
  return true;
}

void NewtonSolver::solve_direction(const Model& model, const Quadrature& quad, const Eigen::Ref<const MatX>& r,
                                   Eigen::Ref<MatX> dq) {
  if (factor_dense_) dense_->solve(r, dq);
  else newton_solve(model, quad, del_factor_, factor_, r, dq);
}

bool NewtonSolver::direction(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                             const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt,
                             const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  const bool ok = factor(model, quad, opt, qc, u, dt);
  if (ok) solve_direction(model, quad, r, dq);
  factor_valid_ = false;
  return ok && dq.allFinite();
}

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
  factor_valid_ = false;  // every solve starts from a fresh factorisation at its guess
  bool reuse = opt.reuse != Reuse::Never;  // may the kept factorisation serve this iteration?
  double previous_dq = INFINITY;       // ||dq||_inf of the previous iteration of this solve
  double smallest = INFINITY;          // the smallest trusted correction so far
  for (;;) {
    if (!std::isfinite(norm2) || !p_next.allFinite()) {
      info.status = SolveStatus::NonFinite;
      return info;
    }
    if (opt.tol > 0 && info.residual <= target) {
      info.status = SolveStatus::Converged;
      return info;
    }
    if (info.iterations >= opt.max_iterations) {
      info.status = SolveStatus::MaxIterations;
      return info;
    }
    // A fresh factorisation at the current iterate unless the kept one still serves (a
    // simplified Newton step).
    const bool fresh = !(reuse && factor_valid_);
    if (fresh) {
      if (!factor(model, quad, opt, qc, u, dt)) {
        info.status = SolveStatus::SingularJacobian;
        return info;
      }
      ++info.factorizations;
    }
    solve_direction(model, quad, r_, dq_);
    ++info.iterations;
    if (!dq_.allFinite()) {
      if (!fresh) {  // the kept Jacobian no longer fits: refactor here
        reuse = false;
        continue;
      }
      info.status = SolveStatus::NonFinite;
      return info;
    }
    // The next correction estimates the error of the iterate: stop when it is at round-off
    // (without applying it, so that q^{k,1..s} and p^{k+1} stay consistent).
    const double dq_max = dq_.cwiseAbs().maxCoeff();
    // A kept factorisation from another iterate may give a small correction to a large
    // residual: it is trusted only after it has been seen contracting in this solve.
    const bool trusted = fresh || dq_max <= opt.reuse_contraction * previous_dq;
    // (The floor test compares with the smallest trusted correction so far: at the floor, noise
    // can pass a damped step, after which the previous correction says nothing.)
    if (trusted && correction_converged(opt, dq_max, smallest, qc.cwiseAbs().maxCoeff(), fresh)) {
      info.status = SolveStatus::Converged;
      return info;
    }
    if (trusted) smallest = std::min(smallest, dq_max);
    if (!trusted) {  // a kept Jacobian contracting slowly: refactor here
      reuse = false;
      continue;
    }
    const double dq_norm = dq_.norm();
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
      solve_direction(model, quad, r_trial_, dbar_);                   // simplified correction
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
      // The exact correction says the iterate is within 1e-10 (1 + ||q||) of the solution, yet
      // no fraction of it reduces the residual: the residual is at its round-off floor.
      const bool at_floor = dq_max <= 1e-10 * (1 + qc.cwiseAbs().maxCoeff());
      info.status = at_floor ? SolveStatus::Converged : SolveStatus::LineSearchFailed;
      return info;
    }
    reuse = opt.reuse != Reuse::Never && lambda == 1;  // after a damped step the Jacobian is refactored
    const bool have_theta = lambda == 1 && previous_dq < INFINITY;
    const double theta = have_theta ? dq_max / previous_dq : 1;  // observed contraction
    previous_dq = lambda == 1 ? dq_max : INFINITY;
    std::swap(del, del_trial_);
    qc = q_trial_;
    r_.swap(r_trial_);
    p_next = p_trial_;
    norm2 = r_.norm();
    info.residual = r_.cwiseAbs().maxCoeff();
    // The error of the new iterate, estimated from the contraction: θ/(1-θ) ||dq_k||.
    if (have_theta && theta < 0.5 &&
        theta / (1 - theta) * dq_max <= opt.step_tol * (1 + qc.cwiseAbs().maxCoeff()) && p_next.allFinite()) {
      info.status = SolveStatus::Converged;
      return info;
    }
  }
}

}  // namespace hovi
