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

// The constrained DEL equations of one step as a Problem of newton_iterate (newton_driver.hpp):
// the iterate is (q^{k,1..s}, λ), every iteration refactors, a damped step is accepted on
// Armijo's test on the merit ||(r, h)||_2, and the convergence tests apply on the manifold only.
struct ConstrainedSolver::Step {
  ConstrainedSolver& sv;
  const SolverOptions& opt;
  const Eigen::Ref<const VecX>& p;
  const Eigen::Ref<const MatX>& u;
  double dt;
  Eigen::Ref<MatX>& qc;
  Eigen::Ref<MatX>& lambda;
  Eigen::Ref<VecX>& p_next;
  double phi = 0;  // the merit at the iterate

  static double merit(const MatX& r, const MatX& H) { return std::sqrt(r.squaredNorm() + H.squaredNorm()); }
  double constraint_norm() const { return sv.H_.size() ? sv.H_.cwiseAbs().maxCoeff() : 0.0; }
  double residual_norm() const { return std::max(stationarity(), constraint_norm()); }
  double stationarity() const { return sv.r_.cwiseAbs().maxCoeff(); }
  bool finite() const { return std::isfinite(phi) && p_next.allFinite(); }
  bool feasible() const { return constraint_norm() <= opt.constraint_tol; }
  double iterate_norm() const { return qc.cwiseAbs().maxCoeff(); }
  bool has_factor() const { return false; }
  Factor factor() {
    if (sv.direction(dt, sv.r_, sv.H_, sv.dz_, sv.dlambda_)) return Factor::Ok;
    return sv.dz_.allFinite() ? Factor::Singular : Factor::NonFinite;
  }
  void direction() const {}  // factor() solved the KKT system
  bool direction_finite() const { return true; }
  double correction_norm() const { return sv.dz_.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double step) {
    sv.q_trial_ = qc;
    sv.q_trial_.rightCols(sv.s_) += step * sv.dz_;
    sv.lambda_trial_ = lambda + step * sv.dlambda_;
    sv.evaluate(p, u, sv.lambda_trial_, dt, sv.q_trial_, sv.r_trial_, sv.H_trial_, sv.p_trial_);
  }
  bool sufficient_decrease(double step) const {
    const double trial = merit(sv.r_trial_, sv.H_trial_);
    return std::isfinite(trial) && trial <= (1 - 1e-4 * step) * phi;
  }
  void commit() {
    qc = sv.q_trial_;
    lambda = sv.lambda_trial_;
    sv.r_.swap(sv.r_trial_);
    sv.H_.swap(sv.H_trial_);
    p_next = sv.p_trial_;
    phi = merit(sv.r_, sv.H_);
  }
  int restore() {  // the outputs back at the iterate
    sv.evaluate(p, u, lambda, dt, qc, sv.r_, sv.H_, p_next);
    return 1;
  }
};

SolveInfo ConstrainedSolver::solve(const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                                   const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc,
                                   Eigen::Ref<MatX> lambda, Eigen::Ref<VecX> p_next) {
  evaluate(p, u, lambda, dt, qc, r_, H_, p_next);
  Step step{*this, opt, p, u, dt, qc, lambda, p_next};
  step.phi = Step::merit(r_, H_);
  NewtonLoop loop = newton_loop(opt, aug_, false);
  loop.reuse = false;                      // every constrained iteration refactors
  loop.estimate_from_contraction = false;
  return newton_iterate(step, stopping_rule(opt, p), loop);
}

}  // namespace hovi
