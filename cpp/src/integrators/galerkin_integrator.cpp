#include "hovi/integrators/galerkin_integrator.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/algorithms/tangent_velocity.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/dense_direction.hpp"

namespace hovi {

namespace {
Model checked(Model model) {
  if (model.n() == 0) throw ModelError("the model has no joints");
  return model;
}
}  // namespace

IntegratorWorkspace::IntegratorWorkspace(const Model& model, const Quadrature& quad)
    : solver(model, quad),
      constrained(model.n_constraints() ? std::make_unique<ConstrainedSolver>(model, quad) : nullptr),
      data(model),
      flow(model) {}

GalerkinIntegrator::GalerkinIntegrator(Model model, int s, double dt, SolverOptions opt)
    : options(opt), model_(checked(std::move(model))), quad_(s), dt_(dt),
      pool_([this] { return std::make_unique<IntegratorWorkspace>(model_, quad_); }) {
  check_newton_options(dt, opt.tol, false, opt.max_iterations, opt.max_backtracks);
  if (!(opt.step_tol > 0) || !std::isfinite(opt.step_tol)) throw InputError("step_tol must be positive");
  if (!(opt.reuse_contraction > 0 && opt.reuse_contraction < 1))
    throw InputError("reuse_contraction must lie in (0, 1)");
  // E(b, a) = l_b(1 + c^a): the previous step's polynomial evaluated at this step's points.
  extrapolate_.resize(s + 1, s + 1);
  for (int a = 0; a <= s; ++a) extrapolate_.col(a) = quad_.basis(1 + quad_.c[a]);
  // Both predictors are shifted to pass through q^{k,0}: columns a = 1..s minus column 0.
  extrapolate_ = (extrapolate_.rightCols(s).colwise() - extrapolate_.col(0)).eval();
  // Least-squares extrapolation from the points of the last two steps, at times (in steps)
  // -2 + c^a (a = 0..s) and -1 + c^a (a = 1..s), to this step's c^a.
  const int degree = std::min(std::max(2, 2 * s - 1), 7);
  MatX V(2 * s + 1, degree + 1), Vt(s + 1, degree + 1);
  for (int i = 0; i <= 2 * s; ++i) {
    const double t = i <= s ? -2 + quad_.c[i] : -1 + quad_.c[i - s];
    for (int d = 0; d <= degree; ++d) V(i, d) = std::pow(t, d);
  }
  for (int a = 0; a <= s; ++a)
    for (int d = 0; d <= degree; ++d) Vt(a, d) = std::pow(quad_.c[a], d);
  extrapolate2_ = (Vt * V.completeOrthogonalDecomposition().pseudoInverse()).transpose();
  extrapolate2_ = (extrapolate2_.rightCols(s).colwise() - extrapolate2_.col(0)).eval();
  pool_.acquire();  // one workspace made up front: a bad model fails here, not in the first call
}

VecX GalerkinIntegrator::momentum(const VecX& q, const VecX& qdot) const {
  check_vector("qdot", qdot, model_.n());
  auto ws = pool_.acquire();
  return mass_matrix(model_, ws->data, q) * qdot;  // O(n^2); used once per trajectory
}

VecX GalerkinIntegrator::velocity(const VecX& q, const VecX& p) const {
  auto ws = pool_.acquire();
  return velocity_from_momentum(model_, ws->data, q, p);
}

double GalerkinIntegrator::energy(const VecX& q, const VecX& p) const {
  auto ws = pool_.acquire();
  const VecX qdot = velocity_from_momentum(model_, ws->data, q, p);
  return kinetic_energy(model_, ws->data, q, qdot) + potential_energy(model_, ws->data, q);
}

MatX GalerkinIntegrator::lambda_guess(const MatX* lambda) const {
  const int mc = model_.n_constraints();
  if (!lambda || !mc) return MatX::Zero(mc, quad_.s);
  if (lambda->rows() != mc || lambda->cols() != quad_.s)
    throw InputError("multipliers must have shape (s, m_c) = (" + std::to_string(quad_.s) + ", " + std::to_string(mc) + ")");
  return *lambda;
}

SolveInfo GalerkinIntegrator::step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
                                   const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                                   MatX& lambda) const {
  if (ws.constrained) {
    MatX trial = lambda;
    const SolveInfo info = ws.constrained->solve(options, p, u, dt_, qc, trial, p_next);
    if (info.converged()) lambda = trial;
    return info;
  }
  return ws.solver.solve(model_, quad_, options, p, u, dt_, qc, p_next);
}

SolveInfo GalerkinIntegrator::step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                   Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, MatX* lambda) const {
  MatX lam = lambda_guess(lambda);
  auto ws = pool_.acquire();
  const SolveInfo info = step(*ws, p, u, qc, p_next, lam);
  if (lambda && model_.n_constraints()) *lambda = lam;
  return info;
}

VecX GalerkinIntegrator::constraint_values(const VecX& q) const {
  auto ws = pool_.acquire();
  forward_kinematics(model_, ws->data, q);
  VecX h(model_.n_constraints());
  hovi::constraint_values(model_, KinematicsView{model_, ws->data.g.data(), ws->data.Sbar.data(), 1}, q, h);
  return h;
}

MatX GalerkinIntegrator::constraint_jacobian(const VecX& q) const {
  auto ws = pool_.acquire();
  forward_kinematics(model_, ws->data, q);
  MatX J(model_.n_constraints(), model_.n());
  hovi::constraint_jacobian(model_, KinematicsView{model_, ws->data.g.data(), ws->data.Sbar.data(), 1}, J);
  return J;
}

std::pair<VecX, VecX> GalerkinIntegrator::project(const VecX& q0, const VecX& qdot0, double tol) const {
  const int n = model_.n(), m = model_.n_constraints();
  check_vector("q", q0, n);
  check_vector("qdot", qdot0, n);
  if (m == 0) return {q0, qdot0};
  VecX q = q0;
  for (int it = 0;; ++it) {
    const VecX h = constraint_values(q);
    const MatX J = constraint_jacobian(q);
    const Eigen::FullPivLU<MatX> lu(J);
    if (lu.rank() < m)
      throw InputError("the constraints are redundant or singular here: the constraint Jacobian has rank " +
                       std::to_string(lu.rank()) + " < " + std::to_string(m) + " equations");
    if (lu.rank() >= n) throw InputError("the constraints leave no degree of freedom (" + std::to_string(m) +
                                         " independent equations for " + std::to_string(n) + " joints)");
    if (h.cwiseAbs().maxCoeff() <= tol) break;
    if (it == 50 || !h.allFinite())
      throw InputError("the initial configuration is too far from the constraint manifold (or the constraints are "
                       "inconsistent): Gauss-Newton left |h| = " + std::to_string(h.cwiseAbs().maxCoeff()));
    q -= J.transpose() * (J * J.transpose()).ldlt().solve(h);  // minimum-norm correction
  }
  auto ws = pool_.acquire();
  return {q, tangent_velocity(model_, ws->data, q, qdot0)};
}

SolveInfo GalerkinIntegrator::robust_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
                                          const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& before_previous,
                                          const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc,
                                          Eigen::Ref<VecX> p_next, MatX& lambda, bool flow) const {
  SolveInfo total;
  for (int attempt = previous.size() ? 0 : 1; attempt < 3; ++attempt) {
    if (attempt == 0) {
      const bool flowed = flow && !ws.constrained && ws.flow.predict(model_, quad_, dt_, ws.data, p, u, qc);
      if (!flowed && before_previous.size()) guess_from_history(before_previous, previous, qc);
      else if (!flowed) guess_from_previous(previous, qc);
    } else if (attempt == 1) guess_from_velocity(velocity_from_momentum(model_, ws.data, qc.col(0), p), qc);
    else qc.rightCols(quad_.s).colwise() = VecX(qc.col(0));
    const SolveInfo info = step(ws, p, u, qc, p_next, lambda);
    total.status = info.status;
    total.iterations += info.iterations;
    total.factorizations += info.factorizations;
    total.residual_evaluations += info.residual_evaluations;
    total.residual = info.residual;
    if (info.converged()) break;
  }
  if (!total.converged() && !ws.constrained) {
    // Last attempt: follow the solution branch from q^k in the step length.
    if (!ws.continuation) ws.continuation = std::make_unique<ContinuationWorkspace>(model_, quad_);
    const SolveInfo info =
        step_continuation(ws.solver, *ws.continuation, model_, quad_, options, p, u, dt_, qc, p_next);
    total.status = info.status;
    total.iterations += info.iterations;
    total.factorizations += info.factorizations;
    total.residual_evaluations += info.residual_evaluations;
    total.residual = info.residual;
  }
  return total;
}

SolveInfo GalerkinIntegrator::robust_step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                          const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc,
                                          Eigen::Ref<VecX> p_next, MatX* lambda) const {
  MatX lam = lambda_guess(lambda);
  auto ws = pool_.acquire();
  const SolveInfo info = robust_step(*ws, p, u, MatX(), previous, qc, p_next, lam);
  if (lambda && model_.n_constraints()) *lambda = lam;
  return info;
}

SolveInfo GalerkinIntegrator::robust_step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                          const Eigen::Ref<const MatX>& before_previous,
                                          const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc,
                                          Eigen::Ref<VecX> p_next) const {
  if (model_.n_constraints()) throw InputError("robust_step from a history: the model has constraints");
  MatX lam = lambda_guess(nullptr);
  auto ws = pool_.acquire();
  return robust_step(*ws, p, u, before_previous, previous, qc, p_next, lam);
}

void GalerkinIntegrator::guess_from_velocity(const VecX& qdot, Eigen::Ref<MatX> qc) const {
  for (int a = 1; a <= quad_.s; ++a) qc.col(a) = qc.col(0) + (quad_.c[a] * dt_) * qdot;
}

void GalerkinIntegrator::guess_from_history(const Eigen::Ref<const MatX>& before_previous,
                                            const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc) const {
  const int s = quad_.s;  // (lazy products: no temporaries, no allocation)
  qc.rightCols(s).noalias() = before_previous.lazyProduct(extrapolate2_.topRows(s + 1)) +
                              previous.rightCols(s).lazyProduct(extrapolate2_.bottomRows(s));
  qc.rightCols(s).colwise() += qc.col(0);
}

void GalerkinIntegrator::guess_from_previous(const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc) const {
  // Keep q^{k,0} exactly and shift the extrapolation to pass through it.
  qc.rightCols(quad_.s).noalias() = previous.lazyProduct(extrapolate_);
  qc.rightCols(quad_.s).colwise() += qc.col(0);
}

void GalerkinIntegrator::start_rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, Rollout& out,
                                       bool hooked) const {
  const int n = model_.n(), S1 = quad_.s + 1, m = model_.n_controls();
  check_vector("q0", q0, n);
  check_vector("p0", p0, n);
  if (N < 0) throw InputError("the number of steps must be non-negative");
  if (hooked) out.controls.setZero(N, S1 * m);
  if (m > 0 && !hooked && (u.rows() != N || u.cols() != S1 * m))
    throw InputError("controls must have shape (steps, s+1, m) = (" + std::to_string(N) + ", " + std::to_string(S1) +
                     ", " + std::to_string(m) + ")");
  if (m > 0 && !hooked && !u.allFinite()) throw InputError("controls contain NaN or infinity");
  out.q.resize(N + 1, n);
  out.p.resize(N + 1, n);
  out.control_points.resize(N, S1 * n);
  out.iterations.resize(N);
  out.factorizations.resize(N);
  out.residual.resize(N);
  out.status.reserve(N);
  out.q.row(0) = q0.transpose();
  out.p.row(0) = p0.transpose();
}

void GalerkinIntegrator::step_controls(const MatX& u, int k, MatX& uk) const {
  const int S1 = quad_.s + 1, m = model_.n_controls();
  uk.resize(m, S1);
  for (int a = 0; a < S1; ++a)
    for (int j = 0; j < m; ++j) uk(j, a) = u(k, a * m + j);
}

void GalerkinIntegrator::hooked_controls(StepHook& hook, int k, Rollout& out, VecX& p, MatX& uk) const {
  const int m = model_.n_controls();
  uk.setZero(m, quad_.s + 1);
  hook.before_step(k, out.q.row(k).transpose(), p, uk);
  if (uk.rows() != m || uk.cols() != quad_.s + 1 || !uk.allFinite() || !p.allFinite())
    throw InputError("the controller gave controls of the wrong shape, or NaN or infinity, at step " + std::to_string(k));
  out.p.row(k) = p.transpose();
  out.controls.row(k) = Eigen::Map<const VecX>(uk.data(), uk.size()).transpose();
}

void GalerkinIntegrator::record_step(Rollout& out, int k, const SolveInfo& info, const Eigen::Ref<const MatX>& qc,
                                     const Eigen::Ref<const VecX>& p_next) const {
  out.status.push_back(info.status);
  out.iterations[k] = info.iterations;
  out.factorizations[k] = info.factorizations;
  out.residual[k] = info.residual;
  if (!info.converged()) return;
  out.q.row(k + 1) = qc.col(quad_.s).transpose();
  out.p.row(k + 1) = p_next.transpose();
  out.control_points.row(k) = Eigen::Map<const VecX>(qc.data(), qc.size()).transpose();
  out.steps = k + 1;
}

Rollout GalerkinIntegrator::rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, const MatX& previous,
                                    const MatX& lambda0, StepHook* hook) const {
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), mc = model_.n_constraints();
  Rollout out;
  start_rollout(q0, p0, N, u, out, hook != nullptr);
  if (previous.size() && (previous.rows() != n || previous.cols() != S1))
    throw InputError("previous control points must have shape (n, s+1)");
  MatX lambda = lambda_guess(lambda0.size() ? &lambda0 : nullptr);
  out.multipliers.resize(N, s * mc);
  auto ws = pool_.acquire();
  MatX qc(n, S1), prev = previous, prev2, uk(m, S1);
  VecX p = p0, p_next(n);
  PredictorChoice predictor(options.predictor, s, uses_dense_direction(options.direction, model_, s));
  for (int k = 0; k < N; ++k) {
    qc.col(0) = out.q.row(k).transpose();
    if (hook) {
      hooked_controls(*hook, k, out, p, uk);
    } else if (m > 0) {
      step_controls(u, k, uk);
    }
    const bool predicted = prev2.size() > 0;  // the history of two steps (before: robust_step's guesses)
    const bool flow = predicted && predictor.flow();
    const SolveInfo info = robust_step(*ws, p, uk, prev2, prev, qc, p_next, lambda, flow);
    if (predicted) predictor.observe(flow, info.iterations);
    record_step(out, k, info, qc, p_next);
    if (!info.converged()) break;
    if (mc) out.multipliers.row(k) = Eigen::Map<const VecX>(lambda.data(), lambda.size()).transpose();
    p = p_next;
    if (prev.size()) prev2.swap(prev);
    prev = qc;
  }
  return out;
}

void GalerkinIntegrator::residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p,
                                  const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> r, Eigen::Ref<VecX> p_next) const {
  auto ws = pool_.acquire();
  del_residual(model_, quad_, ws->solver.del, qc, p, u, dt_, r, p_next);
}

bool GalerkinIntegrator::direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p,
                                   const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> dq) const {
  MatX r(model_.n(), quad_.s);
  VecX p_next(model_.n());
  auto ws = pool_.acquire();
  del_residual(model_, quad_, ws->solver.del, qc, p, u, dt_, r, p_next);
  const bool ok = ws->solver.direction(model_, quad_, options, qc, u, dt_, r, dq);
  return ok;
}

void GalerkinIntegrator::constrained_residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                                              const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                              MatX& r, MatX& H, Eigen::Ref<VecX> p_next) const {
  auto ws = pool_.acquire();
  if (!ws->constrained) throw InputError("the model has no constraints");
  ws->constrained->evaluate(p, u, lambda, dt_, qc, r, H, p_next);
}

bool GalerkinIntegrator::constrained_direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                                               const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                               MatX& dz, MatX& dlambda) const {
  auto ws = pool_.acquire();
  if (!ws->constrained) throw InputError("the model has no constraints");
  MatX r, H;
  VecX p_next(model_.n());
  ws->constrained->evaluate(p, u, lambda, dt_, qc, r, H, p_next);
  return ws->constrained->direction(dt_, r, H, dz, dlambda);
}

}  // namespace hovi
