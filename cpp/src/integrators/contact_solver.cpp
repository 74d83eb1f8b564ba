#include "hovi/integrators/contact_solver.hpp"

#include <algorithm>
#include <cmath>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

ContactSolver::ContactSolver(const Model& model, const Quadrature& quad, const ContactModel& contacts)
    : model_(model), quad_(quad), contacts_(contacts), n_(model.n()), s_(quad.s), C_(contacts.size()),
      d_(contacts.d()), nz_(contacts.unknowns()), data_(model), del_(model, quad), newton_(model, quad) {
  r_com_ = contacts.points_in_com_frames(model);
  J0_.setZero(3 * C_, n_);
}

void ContactSolver::start(const Eigen::Ref<const VecX>& q0) {
  forward_kinematics(model_, data_, q0);
  const KinematicsView kin{model_, data_.g.data(), data_.Sbar.data(), 1};
  X0_.resize(3, C_);
  J0_.setZero();
  for (int c = 0; c < C_; ++c) {
    Vec3 x;
    body_point_jacobian(kin, contacts_.points[c].body, r_com_.col(c), x, J0_.middleRows(3 * c, 3));
    X0_.col(c) = x;
  }
}

void ContactSolver::evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                             const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& z, State& st) {
  const int pc = contacts_.per_contact();
  st.R0.resize(n_, s_);
  st.p_next.resize(n_);
  del_residual(model_, quad_, del_, qc, p, u, dt, st.R0, st.p_next);
  st.R = st.R0;
  const KinematicsView end{model_, del_.g.data() + s_, del_.Sbar.data() + s_, s_ + 1};  // q^{k,s}
  st.Xe.resize(3, C_);
  st.Je.setZero(3 * C_, n_);
  st.h.resize(C_);
  st.phi.resize(C_);
  st.w.resize(nz_);
  for (int c = 0; c < C_; ++c) {
    Vec3 x;
    body_point_jacobian(end, contacts_.points[c].body, r_com_.col(c), x, st.Je.middleRows(3 * c, 3));
    st.Xe.col(c) = x;
    const auto zc = z.segment(c * pc, pc);
    const Vec3 F = contacts_.world_impulse(z, c);
    st.R.col(0).noalias() += J0_.middleRows(3 * c, 3).transpose() * F;  // the impulse at q^k
    st.h[c] = contacts_.surface(c, x);
    st.phi[c] = x[2] - st.h[c];
    const Vec3 disp = x - X0_.col(c);
    st.w[c * pc] = st.phi[c];
    for (int i = 0; i < d_; ++i) st.w[c * pc + 1 + i] = zc[d_ + 1] + contacts_.D.row(i).dot(disp);
    st.w[c * pc + d_ + 1] = contacts_.mu * zc[0] - zc.segment(1, d_).sum();
  }
  st.nu = z.cwiseMin(st.w);
}

void ContactSolver::evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                             const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& z, MatX& r, VecX& phi,
                             VecX& w, Eigen::Ref<VecX> p_next) {
  start(qc.col(0));
  evaluate(p, u, dt, qc, z, cur_);
  r = cur_.R;
  phi = cur_.phi;
  w = cur_.w;
  p_next = cur_.p_next;
}

VecX ContactSolver::knot_impulse(const Eigen::Ref<const VecX>& z) const {
  VecX out = VecX::Zero(n_);
  for (int c = 0; c < C_; ++c) out.noalias() += J0_.middleRows(3 * c, 3).transpose() * contacts_.world_impulse(z, c);
  return out;
}

bool ContactSolver::factor(const SolverOptions& opt, const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                           double dt) {
  dense_path_ = uses_dense_direction(opt.direction, model_, s_);
  if (!dense_path_) return newton_factor(model_, quad_, del_, newton_);
  if (!dense_) dense_ = std::make_unique<DenseDirection>(model_, quad_);
  return dense_->factor(model_, quad_, qc, u, dt, &del_);
}

void ContactSolver::solve_rhs(const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> out) {
  if (dense_path_) dense_->solve(r, out);
  else newton_solve(model_, quad_, del_, newton_, r, out);
}

bool ContactSolver::linearize() {
  const int pc = contacts_.per_contact(), ns = n_ * s_;
  // W3 = -J^{-1} G: the motion of the step's control points per world impulse at each contact
  // (G F = e_0 (x) Σ_c J0_c^T F_c), so that dy = d0 + W3 F with d0 = -J^{-1} R0.
  W3_.resize(ns, 3 * C_);
  if (dense_path_) {  // the 3C right-hand sides [J0^T; 0] in one blocked solve
    rhs_.setZero(ns, 3 * C_);
    rhs_.topRows(n_) = J0_.transpose();
    dense_->solve_many(rhs_, W3_);
  } else {
    rhs_.setZero(n_, s_);
    for (int j = 0; j < 3 * C_; ++j) {
      rhs_.col(0) = J0_.row(j).transpose();
      Eigen::Map<MatX> wj(W3_.col(j).data(), n_, s_);
      solve_rhs(rhs_, wj);
    }
  }
  // The contact points at q^{k+1} + dy_end move by K F, K = Je W3_end; KE (3C x nz) = K E with the
  // impulse map F = E z (λ along +z, β along D_i, γ none).
  K_.noalias() = cur_.Je * W3_.middleRows((s_ - 1) * n_, n_);
  MatX KE = MatX::Zero(3 * C_, nz_);
  for (int c = 0; c < C_; ++c) {
    KE.col(c * pc) = K_.col(3 * c + 2);
    KE.middleCols(c * pc + 1, d_).noalias() = K_.middleCols(3 * c, 3) * contacts_.D.transpose();
  }
  // The matrix of the LCP w = M z + b of the linearised complements (contact_solver.hpp's rows).
  M_.setZero(nz_, nz_);
  for (int c = 0; c < C_; ++c) {
    const int base = c * pc;
    M_.row(base) = KE.row(3 * c + 2);
    for (int i = 0; i < d_; ++i) {
      M_.row(base + 1 + i).noalias() = contacts_.D.row(i) * KE.middleRows(3 * c, 3);
      M_(base + 1 + i, base + d_ + 1) += 1;
    }
    M_(base + d_ + 1, base) = contacts_.mu;
    M_.row(base + d_ + 1).segment(base + 1, d_).setConstant(-1);
  }
  return M_.allFinite();
}

bool ContactSolver::solve_linearization(const Eigen::Ref<const VecX>& z, std::vector<char>& basis) {
  const int pc = contacts_.per_contact(), ns = n_ * s_;
  d0_.resize(n_, s_);
  solve_rhs(cur_.R0, d0_);
  // The contact points at q^{k+1} + d0_end (a, 3C), and the LCP's right-hand side.
  a_ = Eigen::Map<const VecX>(cur_.Xe.data(), 3 * C_) + cur_.Je * d0_.col(s_ - 1);
  b_.setZero(nz_);
  for (int c = 0; c < C_; ++c) {
    const int base = c * pc;
    b_[base] = a_[3 * c + 2] - cur_.h[c];
    for (int i = 0; i < d_; ++i) b_[base + 1 + i] = contacts_.D.row(i).dot(a_.segment<3>(3 * c) - X0_.col(c));
  }
  if (!b_.allFinite()) return false;
  z_new_.resize(nz_);
  const bool ok = lcp_.solve(M_, b_, z_new_, basis);
  pivots_ += lcp_.pivots();
  if (!ok) return false;
  F_.resize(3 * C_);
  for (int c = 0; c < C_; ++c)
    F_.segment<3>(3 * c) = contacts_.world_impulse(z_new_, c);
  dy_ = d0_;
  Eigen::Map<VecX>(dy_.data(), ns).noalias() += W3_ * F_;
  dz_ = z_new_ - z;
  return true;
}

// The contact step as a Problem of newton_iterate (newton_driver.hpp): the iterate is (q^{k,1..s},
// z); every iteration refactors and solves its LCP; a damped step is accepted on Armijo's test on
// ||(r, min(z, w))||_2; the convergence tests apply once every |min(z_i, w_i)| is within tol.
struct ContactSolver::Step {
  ContactSolver& sv;
  double tol;
  const Eigen::Ref<const VecX>& p;
  const Eigen::Ref<const MatX>& u;
  double dt;
  Eigen::Ref<MatX>& qc;
  Eigen::Ref<VecX>& z;
  std::vector<char>& basis;
  double phi_merit = 0;
  bool fresh_lcp = false;  // z_new_ solves the LCP at the current iterate (no step committed since)

  static double merit(const State& st) { return std::sqrt(st.R.squaredNorm() + st.nu.squaredNorm()); }
  double complementarity() const { return sv.cur_.nu.size() ? sv.cur_.nu.cwiseAbs().maxCoeff() : 0.0; }
  double residual_norm() const { return std::max(stationarity(), complementarity()); }
  double stationarity() const { return sv.cur_.R.cwiseAbs().maxCoeff(); }
  bool finite() const { return std::isfinite(phi_merit) && sv.cur_.p_next.allFinite(); }
  bool feasible() const { return complementarity() <= tol; }
  double iterate_norm() const { return qc.rightCols(sv.s_).cwiseAbs().maxCoeff(); }
  const SolverOptions& opt;
  bool factored = false;  // a factorisation (dense path) and its LCP matrix kept from an earlier iterate
  bool solved = true;     // the last direction()'s LCP had a solution
  bool has_factor() const { return factored; }
  Factor factor() {
    factored = false;
    if (!sv.factor(opt, qc, u, dt)) return Factor::Singular;
    if (!sv.linearize()) return Factor::NonFinite;
    factored = sv.dense_path_;  // the recursive factorisation reads the kinematics of its iterate: not kept
    return Factor::Ok;
  }
  void direction() {  // the LCP of the linearisation (its matrix from the kept factorisation) at this iterate
    solved = sv.solve_linearization(z, basis);
    fresh_lcp = solved;
  }
  bool direction_finite() const { return solved && sv.dy_.allFinite() && sv.dz_.allFinite(); }
  double correction_norm() const { return sv.dy_.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double step) {
    sv.q_trial_ = qc;
    sv.q_trial_.rightCols(sv.s_) += step * sv.dy_;
    sv.z_trial_ = z + step * sv.dz_;
    sv.evaluate(p, u, dt, sv.q_trial_, sv.z_trial_, sv.trial_);
  }
  bool sufficient_decrease(double step) const {
    const double t = merit(sv.trial_);
    return std::isfinite(t) && t <= (1 - 1e-4 * step) * phi_merit;
  }
  void commit() {
    qc = sv.q_trial_;
    z = sv.z_trial_;
    std::swap(sv.cur_, sv.trial_);
    phi_merit = merit(sv.cur_);
    fresh_lcp = false;
  }
  int restore() {  // the workspace back at the iterate
    sv.evaluate(p, u, dt, qc, z, sv.cur_);
    return 1;
  }
};

SolveInfo ContactSolver::solve(const SolverOptions& opt, double tol, const Eigen::Ref<const VecX>& p,
                               const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> z,
                               std::vector<char>& basis, Eigen::Ref<VecX> p_next) {
  pivots_ = 0;
  start(qc.col(0));
  evaluate(p, u, dt, qc, z, cur_);
  Step step{*this, tol, p, u, dt, qc, z, basis, 0.0, false, opt};
  step.phi_merit = Step::merit(cur_);
  NewtonLoop loop = newton_loop(opt, model_, false);
  // Every iteration refactors: keeping the factorisation and the LCP's matrix while the iteration
  // contracts (as the integrator's simplified Newton) was measured no faster (bench/README.md, "Design
  // measurements"): the contraction of one active set is not that of the next.
  loop.reuse = false;
  loop.estimate_from_contraction = false;
  SolveInfo info = newton_iterate(step, stopping_rule(opt, p), loop);
  if (info.status == SolveStatus::NonFinite && !step.solved) info.status = SolveStatus::LcpFailed;
  if (info.converged() && step.fresh_lcp) {
    // Stopped on the DEL correction: the impulses are those of the last LCP, which balance the
    // DEL equations at this iterate (R0 + G z_new = -J dy, at round-off); their complements checked again.
    z = z_new_;
    evaluate(p, u, dt, qc, z, cur_);
    ++info.residual_evaluations;
    info.residual = step.residual_norm();
    if (!step.feasible()) info.status = SolveStatus::LcpFailed;
  }
  p_next = cur_.p_next;
  return info;
}

}  // namespace hovi
