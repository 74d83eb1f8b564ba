#include "hovi/baselines/hermite_simpson.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <Eigen/LU>

#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/errors.hpp"

namespace hovi {

// ---------------------------------------------------------------------------------------------
// Hermite-Simpson
// ---------------------------------------------------------------------------------------------

namespace {
const Model& checked(const Model& model) {
  if (model.n() == 0) throw ModelError("the model has no joints");
  if (!model.wrenches.empty())
    throw ModelError("HermiteSimpson: body wrench elements are not supported (joint forces and gravity only)");
  if (!model.constraints.empty()) throw ModelError("HermiteSimpson: holonomic constraints are not supported");
  return model;
}
}  // namespace

HermiteSimpson::HermiteSimpson(const Model& model, double dt, HermiteSimpsonOptions opt)
    : options(opt), model_(checked(model)), dt_(dt), data_(model_), d1_(model_), dm_(model_) {
  check_newton_options(dt, opt.tol, true, opt.max_iterations, opt.max_backtracks);
  const int n = model_.n();
  J_.resize(2 * n, 2 * n);
  u3_.setZero(model_.n_controls(), 3);
  for (VecX* x : {&q0_, &v0_, &a0_, &q1_, &v1_, &a1_, &qm_, &vm_, &am_}) x->setZero(n);
  for (VecX* x : {&r_, &r_trial_, &z_trial_, &dz_}) x->setZero(2 * n);
}

void HermiteSimpson::set_controls(const MatX& u) {
  const int m = model_.n_controls();
  if (m == 0) return;
  if (u.rows() != m || u.cols() != 3)
    throw InputError("controls must have shape (m, 3) = (" + std::to_string(m) + ", 3), got (" +
                     std::to_string(u.rows()) + ", " + std::to_string(u.cols()) + ")");
  if (!u.allFinite()) throw InputError("controls contain NaN or infinity");
  u3_ = u;
}

VecX HermiteSimpson::joint_force(int point, const VecX& q, const VecX& v) const {
  const JointForces& jf = model_.joint_forces;
  VecX Q = jf.preload - jf.stiffness.cwiseProduct(q) - jf.damping.cwiseProduct(v);  // preload - k q - c v
  if (model_.n_controls() > 0) Q.noalias() += jf.actuation * u3_.col(point);        // + B u
  return Q;
}

void HermiteSimpson::states_from_accelerations(const VecX& z) {
  const int n = model_.n();
  const double h = dt_;
  a1_ = z.head(n);
  am_ = z.tail(n);
  v1_ = v0_ + (h / 6) * (a0_ + 4 * am_ + a1_);                      // v_{k+1}
  q1_ = q0_ + (h / 2) * (v0_ + v1_) + (h * h / 12) * (a0_ - a1_);    // q_{k+1}
  qm_ = 0.5 * (q0_ + q1_) + (h / 8) * (v0_ - v1_);                   // q_m
  vm_ = 0.5 * (v0_ + v1_) + (h / 8) * (a0_ - a1_);                   // v_m
}

void HermiteSimpson::residual(const VecX& z, VecX& r) {
  const int n = model_.n();
  const double h = dt_;
  states_from_accelerations(z);
  if (!z.allFinite() || !q1_.allFinite() || !v1_.allFinite() || !qm_.allFinite() || !vm_.allFinite()) {
    r.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  r.head(n) = (h / 6) * (inverse_dynamics(model_, data_, q1_, v1_, a1_) - joint_force(2, q1_, v1_));      // node k+1
  r.tail(n) = (4 * h / 6) * (inverse_dynamics(model_, data_, qm_, vm_, am_) - joint_force(1, qm_, vm_));  // midpoint
}

void HermiteSimpson::jacobian(const VecX& z, VecX* r) {
  const int n = model_.n();
  const double h = dt_;
  if (options.jacobian == HermiteSimpsonJacobian::FiniteDifference) {
    // Central differences of the reduced residual, 4n evaluations.
    z_trial_ = z;
    VecX rp(2 * n), rm(2 * n);
    for (int j = 0; j < 2 * n; ++j) {
      const double e = 6e-6 * (1 + std::abs(z[j]));
      z_trial_[j] = z[j] + e;
      residual(z_trial_, rp);
      z_trial_[j] = z[j] - e;
      residual(z_trial_, rm);
      z_trial_[j] = z[j];
      J_.col(j) = (rp - rm) / (2 * e);
    }
    states_from_accelerations(z);
    return;
  }
  states_from_accelerations(z);
  if (!z.allFinite() || !q1_.allFinite() || !v1_.allFinite() || !qm_.allFinite() || !vm_.allFinite()) {
    J_.setConstant(std::numeric_limits<double>::quiet_NaN());
    if (r) r->setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  rnea_derivatives(model_, data_, q1_, v1_, a1_, d1_);
  rnea_derivatives(model_, data_, qm_, vm_, am_, dm_);
  if (r) {  // the residual from the same passes: tau = ID(q, v, a)
    r->head(n) = (h / 6) * (d1_.tau - joint_force(2, q1_, v1_));
    r->tail(n) = (4 * h / 6) * (dm_.tau - joint_force(1, qm_, vm_));
  }
  const JointForces& jf = model_.joint_forces;
  for (RneaDerivatives* d : {&d1_, &dm_}) {  // ∂(ID - Q)/∂q += k, ∂/∂v += c
    d->dq.diagonal() += jf.stiffness;
    d->dv.diagonal() += jf.damping;
  }
  // Chain rule through the eliminated collocation conditions:
  // ∂v_{k+1}/∂(a_{k+1}, a_m) = (h/6, 2h/3), ∂q_{k+1} = (0, h²/3), ∂v_m = (-h/24, h/3), ∂q_m = (-h²/48, h²/12).
  const double w1 = h / 6, wm = 4 * h / 6;  // Simpson weights of the two residual rows
  J_.topLeftCorner(n, n) = w1 * (d1_.M + (h / 6) * d1_.dv);
  J_.topRightCorner(n, n) = w1 * ((2 * h / 3) * d1_.dv + (h * h / 3) * d1_.dq);
  J_.bottomLeftCorner(n, n) = wm * (-(h / 24) * dm_.dv - (h * h / 48) * dm_.dq);
  J_.bottomRightCorner(n, n) = wm * (dm_.M + (h / 3) * dm_.dv + (h * h / 12) * dm_.dq);
}

// The reduced collocation residual as a Problem of newton_iterate (newton_driver.hpp): the
// iterate is z = (a_{k+1}, a_m), the direction a dense LU of J = ∂r/∂z (kept while it contracts,
// as the VI's solver), a damped step accepted on Armijo's test on ||r||_2.
struct HermiteSimpson::Step {
  HermiteSimpson& hs;
  VecX& z;
  Eigen::PartialPivLU<MatX>& lu;
  bool have_jacobian;  // J_ is that of z (the analytic Jacobian came with the first residual)
  bool factored = false;
  double norm2 = 0;

  double residual_norm() const { return hs.r_.cwiseAbs().maxCoeff(); }
  double stationarity() const { return residual_norm(); }
  bool finite() const { return std::isfinite(norm2) && z.allFinite(); }
  bool feasible() const { return true; }
  double iterate_norm() const { return z.cwiseAbs().maxCoeff(); }
  bool has_factor() const { return factored; }
  Factor factor() {
    factored = false;
    if (!have_jacobian) hs.jacobian(z);
    have_jacobian = false;
    if (!hs.J_.allFinite()) return Factor::NonFinite;
    lu.compute(hs.J_);
    const VecX pivots = lu.matrixLU().diagonal().cwiseAbs();  // |U_ii|
    if (!(pivots.minCoeff() > 1e-14 * pivots.maxCoeff())) return Factor::Singular;
    factored = true;
    return Factor::Ok;
  }
  void direction() { hs.dz_ = lu.solve(-hs.r_); }  // δz = -J^{-1} r (J of this or an earlier iterate)
  bool direction_finite() const { return hs.dz_.allFinite(); }
  double correction_norm() const { return hs.dz_.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double lambda) {
    hs.z_trial_ = z + lambda * hs.dz_;
    hs.residual(hs.z_trial_, hs.r_trial_);
  }
  bool sufficient_decrease(double lambda) const {  // Armijo on ||r||: the Newton direction decreases it at rate 1
    const double trial2 = hs.r_trial_.norm();
    return std::isfinite(trial2) && trial2 <= (1 - 1e-4 * lambda) * norm2;
  }
  void commit() {
    z = hs.z_trial_;
    hs.r_.swap(hs.r_trial_);
    norm2 = hs.r_.norm();
  }
  int restore() const { return 0; }
};

SolveInfo HermiteSimpson::newton(VecX& z) {
  // Analytic: the first residual comes with the Jacobian (the RNEA derivative pass gives tau).
  const bool analytic = options.jacobian == HermiteSimpsonJacobian::Analytic;
  if (analytic) jacobian(z, &r_);
  else residual(z, r_);
  Eigen::PartialPivLU<MatX> lu(2 * model_.n());
  Step step{*this, z, lu, analytic};
  step.norm2 = r_.norm();
  NewtonLoop loop;
  loop.max_iterations = options.max_iterations;
  loop.max_backtracks = options.max_backtracks;
  loop.line_search = options.line_search;
  loop.reuse = options.reuse_jacobian;
  SolveInfo info = newton_iterate(step, StoppingRule(options.tol, kStepTol, residual_scale_), loop);
  if (!std::isfinite(info.residual) && info.status == SolveStatus::Converged) info.status = SolveStatus::NonFinite;
  states_from_accelerations(z);  // the node values of the returned iterate
  return info;
}

SolveInfo HermiteSimpson::step(const VecX& q, const VecX& v, const MatX& u, VecX& q_next, VecX& v_next,
                               const MatX& guess) {
  const int n = model_.n();
  check_vector("q", q, n);
  check_vector("v", v, n);
  set_controls(u);
  if (guess.size() && (guess.rows() != n || guess.cols() != 2 || !guess.allFinite()))
    throw InputError("guess must be a finite (n, 2) matrix of (a_{k+1}, a_m)");
  q0_ = q;
  v0_ = v;
  a0_ = forward_dynamics(model_, data_, q, v, joint_force(0, q, v));             // a_k = FD(q_k, v_k, tau_k)
  const VecX p = mass_matrix(model_, data_, q) * v;                              // p_k = M(q_k) v_k
  residual_scale_ = 1 + p.cwiseAbs().maxCoeff();
  VecX z(2 * n);
  if (guess.size()) {
    z.head(n) = guess.col(0);
    z.tail(n) = guess.col(1);
  } else {
    z.head(n) = a0_;
    z.tail(n) = a0_;
  }
  const SolveInfo info = newton(z);
  q_next = q1_;
  v_next = v1_;
  return info;
}

HermiteSimpsonRollout HermiteSimpson::rollout(const VecX& q0, const VecX& v0, int N, const MatX& u) {
  const int n = model_.n(), m = model_.n_controls();
  check_vector("q0", q0, n);
  check_vector("v0", v0, n);
  if (N < 0) throw InputError("the number of steps must be non-negative");
  if (m > 0 && (u.rows() != N || u.cols() != 3 * m))
    throw InputError("controls must have shape (steps, 3, m) = (" + std::to_string(N) + ", 3, " + std::to_string(m) + ")");
  if (m > 0 && !u.allFinite()) throw InputError("controls contain NaN or infinity");
  HermiteSimpsonRollout out;
  out.q.resize(N + 1, n);
  out.v.resize(N + 1, n);
  out.a.resize(N + 1, n);
  out.iterations.setZero(N);
  out.residual.setConstant(N, std::numeric_limits<double>::quiet_NaN());
  out.status.reserve(N);
  out.q.row(0) = q0.transpose();
  out.v.row(0) = v0.transpose();
  out.a.setConstant(std::numeric_limits<double>::quiet_NaN());
  MatX uk(m, 3), guess(n, 2);
  VecX q = q0, v = v0, q_next(n), v_next(n);
  VecX A0(n), Am(n), A1(n);  // a at t_{k-1}, t_{k-1/2}, t_k from the previous step
  bool have_previous = false;
  for (int k = 0; k < N; ++k) {
    for (int c = 0; c < 3 && m > 0; ++c) uk.col(c) = u.block(k, c * m, 1, m).transpose();
    SolveInfo total;
    for (int attempt = have_previous ? 0 : 1; attempt < 2; ++attempt) {
      if (attempt == 0) {
        // The previous step's quadratic a(t) extrapolated to τ = 3/2 and 2 (τ in steps from t_{k-1}).
        guess.col(0) = 3 * A0 - 8 * Am + 6 * A1;  // a_{k+1}
        guess.col(1) = A0 - 3 * Am + 3 * A1;      // a_m
      }
      const SolveInfo info = step(q, v, uk, q_next, v_next, attempt == 0 ? guess : MatX());
      total.status = info.status;
      total.iterations += info.iterations;
      total.residual_evaluations += info.residual_evaluations;
      total.residual = info.residual;
      if (info.converged()) break;
    }
    out.status.push_back(total.status);
    out.iterations[k] = total.iterations;
    out.residual[k] = total.residual;
    out.a.row(k) = a0_.transpose();
    if (!total.converged()) break;
    out.q.row(k + 1) = q_next.transpose();
    out.v.row(k + 1) = v_next.transpose();
    out.a.row(k + 1) = a1_.transpose();
    A0 = a0_;
    Am = am_;
    A1 = a1_;
    have_previous = true;
    q = q_next;
    v = v_next;
    out.steps = k + 1;
  }
  return out;
}

VecX HermiteSimpson::collocation_residual(const VecX& q, const VecX& v, const VecX& q_next, const VecX& v_next,
                                          const MatX& u) {
  const int n = model_.n();
  const double h = dt_;
  check_vector("q", q, n);
  check_vector("v", v, n);
  check_vector("q_next", q_next, n);
  check_vector("v_next", v_next, n);
  set_controls(u);
  const VecX ak = forward_dynamics(model_, data_, q, v, joint_force(0, q, v));                // f_k = (v_k, a_k)
  const VecX a1 = forward_dynamics(model_, data_, q_next, v_next, joint_force(2, q_next, v_next));  // f_{k+1}
  const VecX qm = 0.5 * (q + q_next) + (h / 8) * (v - v_next);   // x_m = (x_k + x_{k+1})/2 + h/8 (f_k - f_{k+1})
  const VecX vm = 0.5 * (v + v_next) + (h / 8) * (ak - a1);
  const VecX am = forward_dynamics(model_, data_, qm, vm, joint_force(1, qm, vm));           // f_m
  VecX r(2 * n);
  r.head(n) = q_next - q - (h / 6) * (v + 4 * vm + v_next);      // x_{k+1} - x_k - h/6 (f_k + 4 f_m + f_{k+1})
  r.tail(n) = v_next - v - (h / 6) * (ak + 4 * am + a1);
  return r;
}

}  // namespace hovi
