// The contact stages of GalerkinIntegrator::step (galerkin_integrator.hpp): 3 the gaps after a free
// step, 4 the impact located on its polynomial, 5 the contact solve (contact_solver.hpp).
#include <cmath>
#include <functional>
#include <string>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/tangent_velocity.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"

namespace hovi {

namespace {
// The impact time as a Problem of newton_iterate (newton_driver.hpp): the iterate θ, the residual the
// gap at the end of the free piece of θ dt (each evaluation a DEL solve of that piece), the slope that
// of the free step's interpolant; each step kept within half the distance to 0 and to 1; stops at
// |gap| <= 1e-14, after 4 steps, or when the slope is not negative, a step leaves (0, 1) or a piece's
// solve fails (the last good θ kept).
struct ImpactTime {
  ImpactTime(const GalerkinIntegrator& integ, const MatX& qc, const Eigen::Ref<const MatX>& u,
             const Eigen::Ref<const VecX>& p, NewtonSolver& solver,
             std::function<double(const Eigen::Ref<const VecX>&)> gap, double theta)
      : integ(integ), qc(qc), u(u), p(p), solver(solver), gap(std::move(gap)), theta(theta) {}
  const GalerkinIntegrator& integ;
  const MatX qc;  // the free step's control points
  const Eigen::Ref<const MatX>& u;
  const Eigen::Ref<const VecX>& p;
  NewtonSolver& solver;
  std::function<double(const Eigen::Ref<const VecX>&)> gap;  // the smallest gap at a configuration
  double theta;
  MatX q1, u1;   // the free piece's control points and controls at θ
  VecX p_mid;    // its end momentum
  double g = 0;  // the smallest gap at its end
  double slope = 0, next = 0;
  bool failed = false, in_range = true;
  MatX q_try, u_try;
  VecX p_try;
  SolveInfo solves;  // the pieces' DEL solves, summed

  // The piece's control points and controls at the nodes of [0, t] on the step's polynomials.
  void piece(double t, MatX& q, MatX& uu) const {
    const Quadrature& quad = integ.quadrature();
    const int s = quad.s, m = integ.model().n_controls();
    q.resize(qc.rows(), s + 1);
    uu.resize(m, s + 1);
    for (int a = 0; a <= s; ++a) {
      const VecX l = quad.basis(t * quad.c[a]);
      q.col(a) = qc * l;
      if (m) uu.col(a) = u * l;
    }
    q.col(0) = qc.col(0);
  }
  double poly_gap(double tau) const { return gap(qc * integ.quadrature().basis(tau)); }
  double residual_norm() const { return std::abs(g); }
  double stationarity() const { return std::abs(g); }
  bool finite() const { return !failed; }
  bool feasible() const { return true; }
  double iterate_norm() const { return std::abs(theta); }
  bool has_factor() const { return false; }
  Factor factor() {
    const double h = 1e-6;
    slope = (poly_gap(theta + h) - poly_gap(theta - h)) / (2 * h);
    return slope < 0 ? Factor::Ok : Factor::Singular;
  }
  void direction() {
    next = std::min(std::max(theta - g / slope, 0.5 * theta), std::min(1.0, theta + 0.5 * (1 - theta)));
    in_range = next > 1e-9 && next < 1;
  }
  bool direction_finite() const { return in_range; }
  double correction_norm() const { return std::abs(next - theta); }
  bool accept_direction(double, double) const { return true; }
  void trial(double) {
    piece(next, q_try, u_try);
    p_try.resize(p.size());
    const SolveInfo info =
        solver.solve(integ.model(), integ.quadrature(), integ.options, p, u_try, next * integ.dt(), q_try, p_try);
    solves.iterations += info.iterations;
    solves.factorizations += info.factorizations;
    solves.residual_evaluations += info.residual_evaluations;
    failed = !info.converged();
  }
  bool sufficient_decrease(double) const { return true; }
  void commit() {
    if (failed) return;
    theta = next;
    q1.swap(q_try);
    u1.swap(u_try);
    p_mid.swap(p_try);
    g = gap(q1.col(integ.quadrature().s));
  }
  int restore() const { return 0; }
};
}  // namespace

void GalerkinIntegrator::check_impulses(const VecX& z) const {
  const int nz = contacts_.unknowns();
  if (z.size() != nz || !z.allFinite() || (nz && z.minCoeff() < 0))
    throw InputError("impulses must be " + std::to_string(nz) + " finite numbers >= 0");
}

bool GalerkinIntegrator::free_step_holds(IntegratorWorkspace& ws, const Eigen::Ref<const MatX>& qc,
                                         Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi) const {
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), s = quad_.s;
  MatX X0(3, C);
  forward_kinematics(model_, ws.data, qc.col(0));
  for (int c = 0; c < C; ++c) X0.col(c) = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
  forward_kinematics(model_, ws.data, qc.col(s));
  bool holds = true;
  for (int c = 0; c < C; ++c) {
    const Vec3 x = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
    phi[c] = contacts_.gap(c, x);
    holds = holds && phi[c] >= 0;
    // λ = β = 0; γ the least slack that keeps γ + D_i . disp >= 0 (its cone row μλ - Σβ is 0).
    z.segment(c * pc, pc).setZero();
    z[c * pc + d + 1] = std::max(0.0, (-(contacts_.D * (x - X0.col(c)))).maxCoeff());
  }
  return holds;
}

double GalerkinIntegrator::smallest_gap(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& q) const {
  forward_kinematics(model_, ws.data, q);
  double least = INFINITY;
  for (int c = 0; c < contacts_.size(); ++c) {
    const Vec3 x = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
    least = std::min(least, contacts_.gap(c, x));
  }
  return least;
}

double GalerkinIntegrator::impact_time(IntegratorWorkspace& ws, const Eigen::Ref<const MatX>& qc) const {
  auto gap = [&](double tau) { return smallest_gap(ws, qc * quad_.basis(tau)); };
  if (gap(0.0) < 0) return 0.0;
  // Bracket the first sign change on a grid of the step (finer than any oscillation of a polynomial
  // of degree s <= 16 that matters here), then bisect it to round-off.
  constexpr int kGrid = 32;
  double lo = 0, hi = 1;
  for (int j = 1; j <= kGrid; ++j) {
    const double tau = double(j) / kGrid;
    if (gap(tau) < 0) {
      hi = tau;
      break;
    }
    lo = tau;
  }
  while (hi - lo > 1e-14) {
    const double mid = 0.5 * (lo + hi);
    (gap(mid) < 0 ? hi : lo) = mid;
  }
  return lo;
}

SolveInfo GalerkinIntegrator::split_step(IntegratorWorkspace& ws, double& theta, const Eigen::Ref<const VecX>& p,
                                         const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                                         StepHistory& h, ContactReport& report) const {
  const int s = quad_.s, n = model_.n(), m = model_.n_controls();
  ImpactTime it(*this, qc, u, p, ws.solver, [&](const Eigen::Ref<const VecX>& q) { return smallest_gap(ws, q); },
                theta);
  it.piece(theta, it.q1, it.u1);
  it.p_mid.resize(n);
  SolveInfo total = ws.solver.solve(model_, quad_, options, p, it.u1, theta * dt_, it.q1, it.p_mid);
  if (!total.converged()) return total;
  // The interpolant puts the impact within O(dt^{s+1}); the free piece's end is of order 2s. Newton
  // on θ for the gap at that end (its slope from the interpolant) brings the impact to that order.
  it.g = smallest_gap(ws, it.q1.col(s));
  NewtonLoop loop;
  loop.max_iterations = 4;
  loop.line_search = false;
  loop.estimate_from_contraction = false;
  newton_iterate(it, StoppingRule(1e-14, 0.0, 1.0), loop);
  theta = it.theta;
  total.iterations += it.solves.iterations;
  total.factorizations += it.solves.factorizations;
  total.residual_evaluations += it.solves.residual_evaluations;
  MatX q2(n, s + 1), u2(m, s + 1);
  for (int a = 0; a <= s; ++a) {  // the contact piece from the final θ
    const VecX l2 = quad_.basis(theta + (1 - theta) * quad_.c[a]);
    q2.col(a) = qc * l2;
    if (m) u2.col(a) = u * l2;
  }
  q2.col(0) = it.q1.col(s);
  h.z.setZero();
  h.basis.clear();
  const SolveInfo info =
      ws.contact->solve(options, contact_options_.tol, it.p_mid, u2, (1 - theta) * dt_, q2, h.z, h.basis, p_next);
  report.pivots += ws.contact->lcp_pivots();
  total.add(info);
  if (!info.converged()) return total;
  report.phi = ws.contact->gaps();
  // The recorded control points: the two pieces' polynomials at the step's nodes.
  for (int a = 1; a <= s; ++a) {
    const double c = quad_.c[a];
    qc.col(a) = c <= theta ? VecX(it.q1 * quad_.basis(c / theta)) : VecX(q2 * quad_.basis((c - theta) / (1 - theta)));
  }
  qc.col(s) = q2.col(s);
  return total;
}

SolveInfo GalerkinIntegrator::contact_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p,
                                           const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc,
                                           Eigen::Ref<VecX> p_next, StepHistory& h, ContactReport& report) const {
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), s = quad_.s;
  report.pivots = 0;
  report.impact = 0;
  report.phi.setConstant(C, NAN);
  VecX& z = h.z;
  SolveInfo total;
  bool active = false;  // a contact pushed or rubbed in the step before
  for (int c = 0; c < C; ++c) active = active || z.segment(c * pc, d + 1).cwiseAbs().maxCoeff() > 0;
  bool guessed = false;
  if (!active) {
    total.add(free_step(ws, p, u, qc, p_next, h, false));  // stages 1-2
    if (total.converged() && free_step_holds(ws, qc, z, report.phi)) return total;  // stage 3
    guessed = total.converged();  // the free step, through the terrain, is the contact solve's guess
    h.basis.clear();
    double theta = guessed && contact_options_.locate_impacts ? impact_time(ws, qc) : 0.0;
    if (theta > 1e-9) {  // stage 4: split at the impact; if that fails, the plain contact step below
      const MatX free = qc;
      const SolveInfo info = split_step(ws, theta, p, u, qc, p_next, h, report);
      total.add(info);
      if (info.converged()) {
        report.impact = theta;
        return total;
      }
      qc = free;
      z.setZero();
      h.basis.clear();
    }
  }
  for (int attempt = 0; attempt < 3; ++attempt) {  // stage 5, from the guesses of stage 1
    if (attempt == 0 && !guessed) {
      if (h.previous.size() && h.before_previous.size()) guess_from_history(h.before_previous, h.previous, qc);
      else if (h.previous.size()) guess_from_previous(h.previous, qc);
      else guess_from_velocity(velocity_from_momentum(model_, ws.data, qc.col(0), p), qc);
    } else if (attempt > 0) {
      z.setZero();
      h.basis.clear();
      if (attempt == 1) guess_from_velocity(velocity_from_momentum(model_, ws.data, qc.col(0), p), qc);
      else qc.rightCols(s).colwise() = VecX(qc.col(0));
    }
    const SolveInfo info = ws.contact->solve(options, contact_options_.tol, p, u, dt_, qc, z, h.basis, p_next);
    report.pivots += ws.contact->lcp_pivots();
    total.add(info);
    if (info.converged()) {
      report.phi = ws.contact->gaps();
      return total;
    }
  }
  return total;
}

}  // namespace hovi
