#include "hovi/integrators/constrained_solver.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace hovi {

ConstrainedSolver::ConstrainedSolver(const Model& model, const Quadrature& quad)
    : aug_(with_constraint_forces(model)), quad_(quad), n_(model.n()), s_(quad.s), m_(model.n_controls()),
      mc_(model.n_constraints()), del_(aug_, quad), newton_(aug_, quad) {
  // The constraint objects are needed for h and Dh; the augmented model keeps them aside.
  aug_.constraints = model.constraints;
  uaug_.setZero(m_ + mc_, s_ + 1);
  Dh_.resize(mc_, n_);
  h_.resize(mc_);
  p_trial_.resize(n_);
}

void ConstrainedSolver::evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                 const Eigen::Ref<const MatX>& lambda, double dt, const Eigen::Ref<const MatX>& qc,
                                 MatX& r, MatX& H, Eigen::Ref<VecX> p_next) {
  uaug_.topRows(m_) = u;
  uaug_.bottomLeftCorner(mc_, s_) = lambda;  // λ^{k,s} = 0: no constraint force in p^{k+1}
  uaug_.bottomRightCorner(mc_, 1).setZero();
  r.resize(n_, s_);
  del_residual(aug_, quad_, del_, qc, p, uaug_, dt, r, p_next);
  H.resize(mc_, s_);
  for (int g = 1; g <= s_; ++g) {
    constraint_values(aug_, view(g), qc.col(g), h_);
    H.col(g - 1) = h_;
  }
}

bool ConstrainedSolver::direction(double dt, const MatX& r, const MatX& H, MatX& dz, MatX& dlambda) {
  const int n = n_, s = s_, mc = mc_, sm = s * mc;
  if (!newton_factor(aug_, quad_, del_, newton_)) return false;
  dz.resize(n, s);
  newton_solve(aug_, quad_, del_, newton_, r, dz);  // dz_r = -J^{-1} r
  // W(:, (a, c)) = -J^{-1} C^T e_(a, c): the discrete force w^a dt Dh(q^a)_c^T in residual row a.
  W_.resize(n * s, sm);
  rhs_.resize(n, s);
  for (int a = 0; a < s; ++a) {
    constraint_jacobian(aug_, view(a), Dh_);
    for (int c = 0; c < mc; ++c) {
      rhs_.setZero();
      rhs_.col(a) = (quad_.w[a] * dt) * Dh_.row(c).transpose();
      Eigen::Map<MatX> w(W_.col(a * mc + c).data(), n, s);
      newton_solve(aug_, quad_, del_, newton_, rhs_, w);
    }
  }
  // Schur complement: S dλ = -h - Dh dz_r with S((g, i), (a, c)) = Dh(q^g)_i . W(:, (a, c))^g
  S_.resize(sm, sm);
  schur_rhs_.resize(sm);
  for (int g = 1; g <= s; ++g) {
    constraint_jacobian(aug_, view(g), Dh_);
    S_.middleRows((g - 1) * mc, mc).noalias() = Dh_ * W_.middleRows((g - 1) * n, n);
    schur_rhs_.segment((g - 1) * mc, mc) = -H.col(g - 1) - Dh_ * dz.col(g - 1);
  }
  const Eigen::PartialPivLU<MatX> lu(S_);
  const double scale = S_.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-13 * scale))
    return false;  // redundant constraints or a locked mechanism
  const VecX dl = lu.solve(schur_rhs_);
  Eigen::Map<VecX>(dz.data(), n * s) += W_ * dl;
  dlambda = Eigen::Map<const MatX>(dl.data(), mc, s);
  return dz.allFinite() && dlambda.allFinite();
}

SolveInfo ConstrainedSolver::solve(const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                                   const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc,
                                   Eigen::Ref<MatX> lambda, Eigen::Ref<VecX> p_next) {
  const int s = s_, sm = s * mc_;
  const double target = opt.tol * (1 + (p.size() ? p.cwiseAbs().maxCoeff() : 0.0));
  SolveInfo info;
  evaluate(p, u, lambda, dt, qc, r_, H_, p_next);
  info.residual_evaluations = 1;
  auto merit = [](const MatX& r, const MatX& H) { return std::sqrt(r.squaredNorm() + H.squaredNorm()); };
  double phi = merit(r_, H_);
  double smallest_dz = INFINITY;  // the smallest correction so far (every one is fresh)
  for (;;) {
    info.residual = std::max(r_.cwiseAbs().maxCoeff(), sm ? H_.cwiseAbs().maxCoeff() : 0.0);
    if (!std::isfinite(phi) || !p_next.allFinite()) {
      info.status = SolveStatus::NonFinite;
      return info;
    }
    const bool on_manifold = sm == 0 || H_.cwiseAbs().maxCoeff() <= opt.constraint_tol;
    if (opt.tol > 0 && r_.cwiseAbs().maxCoeff() <= target && on_manifold) {
      info.status = SolveStatus::Converged;
      return info;
    }
    if (info.iterations >= opt.max_iterations) {
      info.status = SolveStatus::MaxIterations;
      return info;
    }
    if (!direction(dt, r_, H_, dz_, dlambda_)) {
      info.status = dz_.allFinite() ? SolveStatus::SingularJacobian : SolveStatus::NonFinite;
      return info;
    }
    ++info.iterations;
    ++info.factorizations;  // every constrained iteration refactors
    // NewtonSolver's stopping rule on the next correction (every iteration here is fresh).
    const double dz_max = dz_.cwiseAbs().maxCoeff();
    if (on_manifold && correction_converged(opt, dz_max, smallest_dz, qc.cwiseAbs().maxCoeff(), true)) {
      info.status = SolveStatus::Converged;
      return info;
    }
    smallest_dz = std::min(smallest_dz, dz_max);
    // Backtracking on the merit ||(r, h)||.
    double step = 1;
    bool accepted = false;
    for (int bt = 0; bt <= (opt.line_search ? opt.max_backtracks : 0); ++bt, step *= 0.5) {
      q_trial_ = qc;
      q_trial_.rightCols(s) += step * dz_;
      lambda_trial_ = lambda + step * dlambda_;
      evaluate(p, u, lambda_trial_, dt, q_trial_, r_trial_, H_trial_, p_trial_);
      ++info.residual_evaluations;
      const double trial = merit(r_trial_, H_trial_);
      if (!opt.line_search || (std::isfinite(trial) && trial <= (1 - 1e-4 * step) * phi)) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      evaluate(p, u, lambda, dt, qc, r_, H_, p_next);
      ++info.residual_evaluations;
      info.status = SolveStatus::LineSearchFailed;
      return info;
    }
    qc = q_trial_;
    lambda = lambda_trial_;
    r_.swap(r_trial_);
    H_.swap(H_trial_);
    p_next = p_trial_;
    phi = merit(r_, H_);
  }
}

}  // namespace hovi
