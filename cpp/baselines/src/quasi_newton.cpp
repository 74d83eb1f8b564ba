#include "hovi/baselines/quasi_newton.hpp"

#include <cmath>
#include <string>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

QuasiNewtonSolver::QuasiNewtonSolver(const Model& model, double dt, QuasiNewtonOptions opt)
    : options(opt), model_(model), quad_(1), dt_(dt), del_(model_, quad_), data_(model_) {
  if (model_.n() == 0) throw ModelError("the model has no joints");
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite, got " + std::to_string(dt));
  if (!(opt.tol > 0)) throw InputError("tol must be positive");
  if (opt.max_iterations < 0) throw InputError("max_iterations must be non-negative");
  const int n = model_.n();
  Sbar_.resize(n);
  Mbar_.resize(n);
  IA_.resize(n);
  U_.resize(n);
  D_.resize(n);
  bias_.resize(n);
  dv_.resize(n);
  uimp_.resize(n);
  r_.resize(n, 1);
  dq_.resize(n);
}

bool QuasiNewtonSolver::factor(const Eigen::Ref<const VecX>& qk) {
  forward_kinematics(model_, data_, qk);  // checks size and finiteness
  for (int i = 0; i < model_.n(); ++i) {
    Sbar_[i] = data_.Sbar[i];
    Mbar_[i] = data_.Mbar[i];
  }
  return factor_articulated();
}

// Articulated-body inertias of the tree at q^k: the part of Lee et al.'s impulse-based forward
// dynamics that does not depend on the impulse (Lee Alg. 3, backward pass; Featherstone's ABA).
// Everything is in hovi's spatial (world) frame, so no frame changes between parent and child.
bool QuasiNewtonSolver::factor_articulated() {
  const int n = model_.n();
  const bool armature = model_.has_armature();
  for (int i = 0; i < n; ++i) IA_[i] = Mbar_[i].matrix();  // Î_i starts as the body's own M̄_i
  for (int i = n - 1; i >= 0; --i) {
    U_[i] = IA_[i] * Sbar_[i];       // U_i = Î_i S̄_i
    D_[i] = Sbar_[i].dot(U_[i]);     // D_i = S̄_i^T Î_i S̄_i, the joint's articulated inertia
    if (armature) D_[i] += model_.armature[i];  // of M(q^k) + diag(a)
    if (!(D_[i] > 1e-14 * (1 + IA_[i].norm()))) return false;  // joint moves no mass: M(q^k) singular
    const int par = model_.parent[i];
    if (par >= 0) IA_[par].noalias() += IA_[i] - U_[i] * U_[i].transpose() / D_[i];  // Î_par += Î_i^a
  }
  return true;
}

// dq = dt M(q^k)^{-1} r: the joint velocity change of the system at rest under the generalized
// impulse Q = dt r (= -dt f in Lee et al.'s sign, Lee Alg. 3), by the impulse-based ABA, O(n).
void QuasiNewtonSolver::direction(const Eigen::Ref<const VecX>& r, Eigen::Ref<VecX> dq) {
  const int n = model_.n();
  for (int i = 0; i < n; ++i) bias_[i].setZero();  // no impulse on the bodies, only at the joints
  // Backward pass: bias impulses β̂_i; with q̇ = 0 there are no velocity-product terms.
  for (int i = n - 1; i >= 0; --i) {
    uimp_[i] = dt_ * r[i] - Sbar_[i].dot(bias_[i]);  // u_i = Q_i - S̄_i^T β̂_i
    const int par = model_.parent[i];
    if (par >= 0) bias_[par] += bias_[i] + U_[i] * (uimp_[i] / D_[i]);  // β̂_par += β̂_i + U_i u_i / D_i
  }
  // Forward pass: velocity changes δq̇_i = (u_i - U_i^T δv̄_par) / D_i, δv̄_i = δv̄_par + S̄_i δq̇_i.
  for (int i = 0; i < n; ++i) {
    const int par = model_.parent[i];
    const Twist dv_par = par >= 0 ? dv_[par] : Twist::Zero();
    dq[i] = (uimp_[i] - U_[i].dot(dv_par)) / D_[i];
    dv_[i] = dv_par + Sbar_[i] * dq[i];
  }
  // Lee et al. add the velocity change to the configuration directly: q^{k+1} += δq̇ (Alg. 3).
}

// The trapezoidal DEL equations as a Problem of newton_iterate (newton_driver.hpp) with the
// fixed matrix J̃ = -(1/dt) M(q^k), factored once, and full steps: Lee et al.'s RIQN takes every
// step as is (Alg. 3, and Skeleton::dm_integrate_RIQN_* in their code).
struct QuasiNewtonSolver::Step {
  QuasiNewtonSolver& sv;
  const Eigen::Ref<const VecX>& p;
  const Eigen::Ref<const MatX>& u;
  Eigen::Ref<MatX>& qc;
  Eigen::Ref<VecX>& p_next;
  bool factored = false;

  double residual_norm() const { return sv.r_.cwiseAbs().maxCoeff(); }
  double stationarity() const { return residual_norm(); }
  bool finite() const { return std::isfinite(residual_norm()) && p_next.allFinite(); }
  bool feasible() const { return true; }
  double iterate_norm() const { return qc.cwiseAbs().maxCoeff(); }
  bool has_factor() const { return factored; }
  Factor factor() {
    factored = sv.factor_articulated();
    return factored ? Factor::Ok : Factor::Singular;
  }
  void direction() { sv.direction(sv.r_.col(0), sv.dq_); }
  bool direction_finite() const { return sv.dq_.allFinite(); }
  double correction_norm() const { return sv.dq_.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double) {
    qc.col(1) += sv.dq_;
    del_residual(sv.model_, sv.quad_, sv.del_, qc, p, u, sv.dt_, sv.r_, p_next);
  }
  bool sufficient_decrease(double) const { return true; }
  void commit() const {}
  int restore() const { return 0; }
};

SolveInfo QuasiNewtonSolver::solve(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                   Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next) {
  const int n = model_.n(), m = model_.n_controls();
  if (qc.rows() != n || qc.cols() != 2)
    throw InputError("qc must be n x 2 (q^k, q^{k+1}), got " + std::to_string(qc.rows()) + " x " +
                     std::to_string(qc.cols()));
  if (p.size() != n || p_next.size() != n) throw InputError("p and p_next must have n entries");
  if (u.rows() != m || u.cols() != 2) throw InputError("u must be m x 2");
  del_residual(model_, quad_, del_, qc, p, u, dt_, r_, p_next);  // Algorithm 1 (Lee: DRNEA, Alg. 2)
  // The approximate Jacobian is fixed at q^k = column 0, whose kinematics Algorithm 1 just computed.
  for (int i = 0; i < n; ++i) {
    Sbar_[i] = del_.Sbar[del_.at(i, 0)];
    Mbar_[i] = del_.Mbar[del_.at(i, 0)];
  }
  Step step{*this, p, u, qc, p_next};
  NewtonLoop loop;
  loop.max_iterations = options.max_iterations;
  loop.line_search = false;
  loop.fixed_jacobian = true;
  return newton_iterate(step, StoppingRule(options.tol, kStepTol, 1 + p.cwiseAbs().maxCoeff()), loop);
}

}  // namespace hovi
