#include "hovi/integrators/newton_solver.hpp"

#include <algorithm>
#include <cmath>

#include "hovi/integrators/dense_direction.hpp"

namespace hovi {

StoppingRule stopping_rule(const SolverOptions& opt, const Eigen::Ref<const VecX>& p) {
  return StoppingRule(opt.tol, opt.step_tol, 1 + (p.size() ? p.cwiseAbs().maxCoeff() : 0.0));
}

NewtonLoop newton_loop(const SolverOptions& opt, const Model& model, bool exact) {
  NewtonLoop loop;
  // a free base's chart on a direction without the chart term's derivative: Newton converges linearly
  // at a rate that varies, so its error is estimated from the larger of the last two contractions, and
  // the last small correction is applied (the iterate's error is about that size); on the exact one
  // it converges quadratically, and a stop on the contraction's estimate takes one correction more
  // (its residual of 1e-12 would move the world momenta)
  const bool chart = model.rotation_chart >= 0;
  loop.steady_contraction = loop.apply_last_correction = chart && !exact;
  loop.correct_after_contraction = chart && exact;
  loop.max_iterations = opt.max_iterations;
  loop.max_backtracks = opt.max_backtracks;
  loop.line_search = opt.line_search;
  loop.reuse = opt.reuse != Reuse::Never;
  loop.reuse_contraction = opt.reuse_contraction;
  return loop;
}

NewtonSolver::NewtonSolver(const Model& model, const Quadrature& quad)
    : del(model, quad), newton(model, quad), del_trial_(model, quad), del_factor_(model, quad), factor_(model, quad),
      r_(model.n(), quad.s),
      r_trial_(model.n(), quad.s), dq_(model.n(), quad.s), dbar_(model.n(), quad.s), q_trial_(model.n(), quad.s + 1),
      p_trial_(model.n()) {}

NewtonSolver::~NewtonSolver() = default;

void NewtonSolver::set_chart_placement(const SE3& placement) {
  del.chart_placement = del_trial_.chart_placement = del_factor_.chart_placement = placement;
  factor_valid_ = false;  // a kept factorisation belongs to the chart it was computed in
}

bool NewtonSolver::factor(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                          const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt,
                          const MatX& r) {
  factor_valid_ = false;
  factor_dense_ = uses_dense_direction(opt.direction, model, quad.s);
  if (factor_dense_) {
    if (!dense_) dense_ = std::make_unique<DenseDirection>(model, quad);
    // del and r hold Algorithm 1 at qc; the chart term's derivative where it pays (exact_chart_direction)
    const bool exact = exact_chart_direction(opt.direction, model, quad.s);
    if (!dense_->factor(model, quad, qc, u, dt, &del, exact ? &r : nullptr)) return false;
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
  const bool ok = factor(model, quad, opt, qc, u, dt, MatX(r));
  if (ok) solve_direction(model, quad, r, dq);
  factor_valid_ = false;
  return ok && dq.allFinite();
}

// The DEL equations of one step as a Problem of newton_iterate (newton_driver.hpp): the
// iterate is q^{k,1..s}, the direction the exact one of factor() (or a kept factorisation), and a
// damped step is accepted on Armijo's test on ||r||_2 or Deuflhard's natural monotonicity test.
struct NewtonSolver::Step {
  NewtonSolver& sv;
  const Model& model;
  const Quadrature& quad;
  const SolverOptions& opt;
  const Eigen::Ref<const VecX>& p;
  const Eigen::Ref<const MatX>& u;
  double dt;
  Eigen::Ref<MatX>& qc;
  Eigen::Ref<VecX>& p_next;
  double norm2 = 0, dq_norm = 0;  // ||r||_2 at the iterate, ||dq||_2

  double residual_norm() const { return sv.r_.cwiseAbs().maxCoeff(); }
  double stationarity() const { return residual_norm(); }
  bool finite() const { return std::isfinite(norm2) && p_next.allFinite(); }
  bool feasible() const { return true; }
  double iterate_norm() const { return qc.cwiseAbs().maxCoeff(); }
  bool has_factor() const { return sv.factor_valid_; }
  Factor factor() { return sv.factor(model, quad, opt, qc, u, dt, sv.r_) ? Factor::Ok : Factor::Singular; }
  void direction() { sv.solve_direction(model, quad, sv.r_, sv.dq_); }
  bool direction_finite() const { return sv.dq_.allFinite(); }
  double correction_norm() { dq_norm = sv.dq_.norm(); return sv.dq_.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double lambda) {
    sv.q_trial_.col(0) = qc.col(0);
    sv.q_trial_.rightCols(quad.s) = qc.rightCols(quad.s) + lambda * sv.dq_;
    del_residual(model, quad, sv.del_trial_, sv.q_trial_, p, u, dt, sv.r_trial_, sv.p_trial_);
  }
  bool sufficient_decrease(double lambda) {
    const double trial2 = sv.r_trial_.norm();
    if (!std::isfinite(trial2) || !sv.p_trial_.allFinite()) return false;
    if (trial2 <= (1 - 1e-4 * lambda) * norm2) return true;              // Armijo on ||r||
    sv.solve_direction(model, quad, sv.r_trial_, sv.dbar_);              // simplified correction
    return sv.dbar_.norm() <= (1 - 0.25 * lambda) * dq_norm;             // natural monotonicity
  }
  void commit() {
    std::swap(sv.del, sv.del_trial_);
    qc = sv.q_trial_;
    sv.r_.swap(sv.r_trial_);
    p_next = sv.p_trial_;
    norm2 = sv.r_.norm();
  }
  int restore() const { return 0; }
};

SolveInfo NewtonSolver::solve(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                              const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                              Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next) {
  del_residual(model, quad, del, qc, p, u, dt, r_, p_next);
  factor_valid_ = false;  // every solve starts from a fresh factorisation at its guess
  Step step{*this, model, quad, opt, p, u, dt, qc, p_next};
  step.norm2 = r_.norm();
  return newton_iterate(step, stopping_rule(opt, p),
                        newton_loop(opt, model, exact_chart_direction(opt.direction, model, quad.s)));
}

}  // namespace hovi
