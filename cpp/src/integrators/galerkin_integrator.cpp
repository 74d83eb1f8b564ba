#include "hovi/integrators/galerkin_integrator.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/algorithms/tangent_velocity.hpp"
#include "hovi/errors.hpp"

namespace hovi {

namespace {
Model checked(Model model) {
  if (model.n() == 0) throw ModelError("the model has no joints");
  if (model.rotation_chart >= 0 && model.n_constraints())
    throw ModelError("holonomic constraints on a model with a free base are not supported yet");
  return model;
}

ContactModel checked(const Model& model, ContactModel contacts, const ContactOptions& opt) {
  if (contacts.size() == 0) return contacts;
  if (model.n_constraints())
    throw InputError("contacts with holonomic constraints are not supported: simulate the model without its "
                     "constraints, or without contacts");
  contacts.check(model);
  // Below 1e-14 the tolerance is under the round-off of the gaps and impulses: no step would meet it.
  if (!(opt.tol >= 1e-14 && opt.tol <= 1e-3)) {
    std::ostringstream os;
    os << "contact_tol must lie in [1e-14, 1e-3] (below 1e-14 it is under the round-off of the gaps), got " << opt.tol;
    throw InputError(os.str());
  }
  return contacts;
}

// The projection onto h(q) = 0 as a Problem of newton_iterate (newton_driver.hpp): Gauss-Newton with
// minimum-norm corrections dq = -Dh^T (Dh Dh^T)^{-1} h, full steps, converged when ||h||_inf <= tol.
// The rank of Dh is checked at every iterate (redundant constraints, or none left free).
struct Projection {
  const GalerkinIntegrator& integ;
  VecX q, h, dq, q_trial;
  MatX J;
  double tol;

  void evaluate() {
    h = integ.constraint_values(q);
    J = integ.constraint_jacobian(q);
    const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
    const Eigen::FullPivLU<MatX> lu(J);
    if (lu.rank() < m)
      throw InputError("the constraints are redundant or singular here: the constraint Jacobian has rank " +
                       std::to_string(lu.rank()) + " < " + std::to_string(m) + " equations");
    if (lu.rank() >= n)
      throw InputError("the constraints leave no degree of freedom (" + std::to_string(m) +
                       " independent equations for " + std::to_string(n) + " joints)");
  }
  double residual_norm() const { return h.cwiseAbs().maxCoeff(); }
  double stationarity() const { return residual_norm(); }
  bool finite() const { return h.allFinite(); }
  bool feasible() const { return residual_norm() <= tol; }
  double iterate_norm() const { return q.cwiseAbs().maxCoeff(); }
  bool has_factor() const { return false; }
  Factor factor() const { return Factor::Ok; }
  void direction() { dq = -J.transpose() * (J * J.transpose()).ldlt().solve(h); }
  bool direction_finite() const { return dq.allFinite(); }
  double correction_norm() const { return dq.cwiseAbs().maxCoeff(); }
  bool accept_direction(double, double) const { return true; }
  void trial(double lambda) { q_trial = q + lambda * dq; }
  bool sufficient_decrease(double) const { return true; }
  void commit() {
    q = q_trial;
    evaluate();
  }
  int restore() const { return 0; }
};
}  // namespace

IntegratorWorkspace::IntegratorWorkspace(const Model& model, const Quadrature& quad, const ContactModel& contacts)
    : solver(model, quad),
      constrained(model.n_constraints() ? std::make_unique<ConstrainedSolver>(model, quad) : nullptr),
      contact(contacts.size() ? std::make_unique<ContactSolver>(model, quad, contacts) : nullptr),
      data(model),
      flow(model) {}

void IntegratorWorkspace::set_chart_centre(const Model& model, const Mat3& centre) {
  const SE3 placement = model.chart_placement(centre);
  solver.set_chart_placement(placement);
  if (contact) contact->set_chart_placement(placement);
  if (continuation) continuation->del_h.chart_placement = continuation->data.chart_placement = placement;
  data.chart_placement = placement;
}

GalerkinIntegrator::GalerkinIntegrator(Model model, int s, double dt, SolverOptions opt, ContactModel contacts,
                                       ContactOptions contact_options)
    : options(opt), model_(checked(std::move(model))),
      contacts_(checked(model_, std::move(contacts), contact_options)), contact_options_(contact_options), quad_(s),
      dt_(dt), pool_([this] { return std::make_unique<IntegratorWorkspace>(model_, quad_, contacts_); }) {
  check_newton_options(dt, opt.tol, false, opt.max_iterations, opt.max_backtracks);
  if (!(opt.step_tol > 0) || !std::isfinite(opt.step_tol)) throw InputError("step_tol must be positive");
  if (!(opt.reuse_contraction > 0 && opt.reuse_contraction < 1))
    throw InputError("reuse_contraction must lie in (0, 1)");
  if (has_contacts()) r_com_ = contacts_.points_in_com_frames(model_);
  if (model_.rotation_chart >= 0) free_base_.emplace(model_);
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
  if (!free_base_) return mass_matrix(model_, ws->data, q) * qdot;  // O(n^2); used once per trajectory
  const auto [qc, C] = chart_state(*ws, q);
  VecX x = qdot;
  free_base_->velocity_to_chart(qc, C, x);
  x = mass_matrix(model_, ws->data, qc) * x;
  free_base_->momentum_to_public(qc, C, x);
  return x;
}

VecX GalerkinIntegrator::velocity(const VecX& q, const VecX& p) const {
  auto ws = pool_.acquire();
  if (!free_base_) return velocity_from_momentum(model_, ws->data, q, p);
  const auto [qc, C] = chart_state(*ws, q);
  VecX x = p;
  free_base_->momentum_to_chart(qc, C, x);
  x = velocity_from_momentum(model_, ws->data, qc, x);
  free_base_->velocity_to_public(qc, C, x);
  return x;
}

double GalerkinIntegrator::energy(const VecX& q, const VecX& p) const {
  auto ws = pool_.acquire();
  if (!free_base_) {
    const VecX qdot = velocity_from_momentum(model_, ws->data, q, p);
    return kinetic_energy(model_, ws->data, q, qdot) + potential_energy(model_, ws->data, q);
  }
  check_vector("p", p, model_.n());
  const auto [qc, C] = chart_state(*ws, q);
  VecX x = p;
  free_base_->momentum_to_chart(qc, C, x);
  const VecX qdot = velocity_from_momentum(model_, ws->data, qc, x);
  return kinetic_energy(model_, ws->data, qc, qdot) + potential_energy(model_, ws->data, qc);
}

std::pair<VecX, Mat3> GalerkinIntegrator::chart_state(IntegratorWorkspace& ws, const VecX& q) const {
  check_vector("q", q, model_.nq());
  VecX qc(model_.n());
  Mat3 C;
  free_base_->split(q, qc, C);
  ws.data.chart_placement = model_.chart_placement(C);
  return {qc, C};
}

MatX GalerkinIntegrator::lambda_guess(const MatX* lambda) const {
  const int mc = model_.n_constraints();
  if (!lambda || !mc) return MatX::Zero(mc, quad_.s);
  if (lambda->rows() != mc || lambda->cols() != quad_.s)
    throw InputError("multipliers must have shape (s, m_c) = (" + std::to_string(quad_.s) + ", " + std::to_string(mc) + ")");
  return *lambda;
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
  const int n = model_.n();
  check_vector("q", q0, n);
  check_vector("qdot", qdot0, n);
  if (model_.n_constraints() == 0) return {q0, qdot0};
  Projection pb{*this, q0, VecX(), VecX(), VecX(), MatX(), tol};
  pb.evaluate();
  NewtonLoop loop;
  loop.max_iterations = 50;
  loop.line_search = false;
  loop.estimate_from_contraction = false;
  const SolveInfo info = newton_iterate(pb, StoppingRule(tol, 0.0, 1.0), loop);
  if (!info.converged())
    throw InputError("the initial configuration is too far from the constraint manifold (or the constraints are "
                     "inconsistent): Gauss-Newton left |h| = " + std::to_string(pb.residual_norm()));
  auto ws = pool_.acquire();
  return {pb.q, tangent_velocity(model_, ws->data, pb.q, qdot0)};
}

SolveInfo GalerkinIntegrator::solve(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
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

SolveInfo GalerkinIntegrator::solve(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                    Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, MatX* lambda) const {
  MatX lam = lambda_guess(lambda);
  auto ws = pool_.acquire();
  const SolveInfo info = solve(*ws, p, u, qc, p_next, lam);
  if (lambda && model_.n_constraints()) *lambda = lam;
  return info;
}

SolveInfo GalerkinIntegrator::free_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
                                        const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                                        StepHistory& h, bool flow) const {
  SolveInfo total;
  for (int attempt = h.previous.size() ? 0 : 1; attempt < 3; ++attempt) {
    if (attempt == 0) {  // stage 1: predict
      const bool flowed = flow && !ws.constrained && ws.flow.predict(model_, quad_, dt_, ws.data, p, u, qc);
      if (!flowed && h.before_previous.size()) guess_from_history(h.before_previous, h.previous, qc);
      else if (!flowed) guess_from_previous(h.previous, qc);
    } else if (attempt == 1) guess_from_velocity(velocity_from_momentum(model_, ws.data, qc.col(0), p), qc);
    else qc.rightCols(quad_.s).colwise() = VecX(qc.col(0));
    total.add(solve(ws, p, u, qc, p_next, h.lambda));  // stage 2: DEL
    if (total.converged()) return total;
  }
  if (!ws.constrained) {  // last: follow the solution branch from q^k in the step length
    if (!ws.continuation) {
      ws.continuation = std::make_unique<ContinuationWorkspace>(model_, quad_);
      ws.continuation->del_h.chart_placement = ws.continuation->data.chart_placement = ws.data.chart_placement;
    }
    total.add(step_continuation(ws.solver, *ws.continuation, model_, quad_, options, p, u, dt_, qc, p_next));
  }
  return total;
}

SolveInfo GalerkinIntegrator::step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
                                   const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                                   StepHistory& h, ContactReport& report, bool flow) const {
  if (free_base_) {
    ws.p_chart = p;
    recentre(ws, qc, h);
    if (!has_contacts()) return free_step(ws, ws.p_chart, u, qc, p_next, h, flow);
    return contact_step(ws, ws.p_chart, u, qc, p_next, h, report);
  }
  if (!has_contacts()) return free_step(ws, p, u, qc, p_next, h, flow);  // stages 1-2
  return contact_step(ws, p, u, qc, p_next, h, report);                  // stages 1-5
}

SolveInfo GalerkinIntegrator::step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                   Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, StepHistory& history,
                                   ContactReport* report) const {
  const int n = model_.n(), s = quad_.s;
  if (qc.rows() != n || qc.cols() != s + 1 || p.size() != n || u.rows() != model_.n_controls() || u.cols() != s + 1)
    throw InputError("step: q^k, p^k and the controls must have n, n and m x (s+1) entries");
  if (history.previous.size() && (history.previous.rows() != n || history.previous.cols() != s + 1))
    throw InputError("previous control points must have shape (n, s+1)");
  history.lambda = lambda_guess(history.lambda.size() ? &history.lambda : nullptr);
  if (history.z.size() == 0) history.z = VecX::Zero(contacts_.unknowns());
  else check_impulses(history.z);
  ContactReport own;
  ContactReport& out = report ? *report : own;
  if (!qc.col(0).allFinite() || !p.allFinite() || !u.allFinite()) {  // a failed step, not an error (FDDP's line search)
    SolveInfo info;
    info.status = SolveStatus::NonFinite;
    info.residual = INFINITY;
    return info;
  }
  auto ws = pool_.acquire();
  return step(*ws, p, u, qc, p_next, history, out, false);
}

void GalerkinIntegrator::recentre(IntegratorWorkspace& ws, Eigen::Ref<MatX> qc, StepHistory& h) const {
  const RotationChart& chart = free_base_->chart;
  const int j = model_.rotation_chart, s = quad_.s;
  const Vec3 theta = qc.col(0).segment<3>(j);
  ws.p_chart.segment<3>(j) = chart.recentred_momentum(theta, ws.p_chart.segment<3>(j));
  h.centre = h.centre * chart.rotation(theta);
  qc.col(0).segment<3>(j).setZero();
  if (h.previous.size()) {  // the history is in the chart of the step that ended at q^k
    const Vec3 last = h.previous.col(s).segment<3>(j);
    chart.recentre_points(j, last, h.previous);
    if (h.before_previous.size()) chart.recentre_points(j, last, h.before_previous);
  }
  ws.set_chart_centre(model_, h.centre);
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
  return ws->solver.direction(model_, quad_, options, qc, u, dt_, r, dq);
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
