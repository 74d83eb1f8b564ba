#include "hovi/contact/contact_integrator.hpp"

#include <cmath>
#include <string>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

namespace {
ContactModel checked(const Model& model, ContactModel contacts) {
  if (model.n_constraints())
    throw InputError("contacts with holonomic constraints are not supported: simulate the model without its "
                     "constraints, or without contacts");
  contacts.check(model);
  return contacts;
}
}  // namespace

ContactIntegrator::ContactIntegrator(Model model, ContactModel contacts, int s, double dt, SolverOptions options,
                                     double tol, bool locate_impacts)
    : free_(std::move(model), s, dt, options), contacts_(checked(free_.model(), std::move(contacts))), tol_(tol),
      locate_(locate_impacts),
      pool_([this] { return std::make_unique<Workspace>(free_.model(), free_.quadrature(), contacts_); }) {
  if (!(tol > 0 && tol <= 1e-3)) throw InputError("contact_tol must lie in (0, 1e-3], got " + std::to_string(tol));
  r_com_ = contacts_.points_in_com_frames(free_.model());
  pool_.acquire();
}

bool ContactIntegrator::free_step_holds(Workspace& ws, const Eigen::Ref<const MatX>& qc, Eigen::Ref<VecX> z,
                                        Eigen::Ref<VecX> phi) const {
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), s = free_.quadrature().s;
  const Model& model = free_.model();
  MatX X0(3, C);
  forward_kinematics(model, ws.data, qc.col(0));
  for (int c = 0; c < C; ++c) X0.col(c) = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
  forward_kinematics(model, ws.data, qc.col(s));
  bool holds = true;
  for (int c = 0; c < C; ++c) {
    const Vec3 x = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
    phi[c] = x[2] - contacts_.terrain.height(x[0], x[1]);
    holds = holds && phi[c] >= 0;
    // λ = β = 0; γ the least slack that keeps γ + D_i . disp >= 0 (its cone row μλ - Σβ is 0).
    z.segment(c * pc, pc).setZero();
    z[c * pc + d + 1] = std::max(0.0, (-(contacts_.D * (x - X0.col(c)))).maxCoeff());
  }
  return holds;
}

double ContactIntegrator::smallest_gap(Workspace& ws, const Eigen::Ref<const VecX>& q) const {
  forward_kinematics(free_.model(), ws.data, q);
  double least = INFINITY;
  for (int c = 0; c < contacts_.size(); ++c) {
    const Vec3 x = ws.data.g[contacts_.points[c].body].act(r_com_.col(c));
    least = std::min(least, x[2] - contacts_.terrain.height(x[0], x[1]));
  }
  return least;
}

double ContactIntegrator::impact_time(Workspace& ws, const Eigen::Ref<const MatX>& qc) const {
  const Quadrature& quad = free_.quadrature();
  auto gap = [&](double tau) { return smallest_gap(ws, qc * quad.basis(tau)); };
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

SolveInfo ContactIntegrator::split_step(Workspace& ws, double& theta, const Eigen::Ref<const VecX>& p,
                                        const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                                        Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi, int& pivots) const {
  const Quadrature& quad = free_.quadrature();
  const int s = quad.s, n = free_.model().n(), m = free_.model().n_controls();
  const double dt = free_.dt();
  // Each piece's control points and controls from the step's polynomials at its nodes.
  MatX q1(n, s + 1), q2(n, s + 1), u1(m, s + 1), u2(m, s + 1);
  for (int a = 0; a <= s; ++a) {
    const VecX l1 = quad.basis(theta * quad.c[a]), l2 = quad.basis(theta + (1 - theta) * quad.c[a]);
    q1.col(a) = qc * l1;
    q2.col(a) = qc * l2;
    if (m) u1.col(a) = u * l1, u2.col(a) = u * l2;
  }
  q1.col(0) = qc.col(0);
  VecX p_mid(n);
  SolveInfo total = ws.newton.solve(free_.model(), quad, free_.options, p, u1, theta * dt, q1, p_mid);
  if (!total.converged()) return total;
  // The interpolant puts the impact within O(dt^{s+1}); the free piece's end is of order 2s. Newton
  // on θ for the gap at that end (its slope from the interpolant) brings the impact to that order.
  auto poly_gap = [&](double tau) { return smallest_gap(ws, qc * quad.basis(tau)); };
  for (int it = 0; it < 4; ++it) {
    const double g = smallest_gap(ws, q1.col(s));
    const double h = 1e-6, slope = (poly_gap(theta + h) - poly_gap(theta - h)) / (2 * h);
    if (!(slope < 0) || std::abs(g) <= 1e-14) break;
    const double next = std::min(std::max(theta - g / slope, 0.5 * theta), std::min(1.0, theta + 0.5 * (1 - theta)));
    if (!(next > 1e-9 && next < 1)) break;
    MatX q_try(n, s + 1), u_try(m, s + 1);
    for (int a = 0; a <= s; ++a) {
      const VecX l = quad.basis(next * quad.c[a]);
      q_try.col(a) = qc * l;
      if (m) u_try.col(a) = u * l;
    }
    q_try.col(0) = qc.col(0);
    VecX p_try(n);
    const SolveInfo info = ws.newton.solve(free_.model(), quad, free_.options, p, u_try, next * dt, q_try, p_try);
    total.iterations += info.iterations;
    total.factorizations += info.factorizations;
    total.residual_evaluations += info.residual_evaluations;
    if (!info.converged()) break;
    theta = next;
    q1 = q_try;
    u1 = u_try;
    p_mid = p_try;
  }
  for (int a = 0; a <= s; ++a) {  // the contact piece from the final θ
    const VecX l2 = quad.basis(theta + (1 - theta) * quad.c[a]);
    q2.col(a) = qc * l2;
    if (m) u2.col(a) = u * l2;
  }
  q2.col(0) = q1.col(s);
  z.setZero();
  ws.basis.clear();
  const SolveInfo info = ws.solver.solve(free_.options, tol_, p_mid, u2, (1 - theta) * dt, q2, z, ws.basis, p_next);
  pivots += ws.solver.lcp_pivots();
  total.status = info.status;
  total.iterations += info.iterations;
  total.factorizations += info.factorizations;
  total.residual_evaluations += info.residual_evaluations;
  total.residual = info.residual;
  if (!info.converged()) return total;
  phi = ws.solver.gaps();
  // The recorded control points: the two pieces' polynomials at the step's nodes.
  for (int a = 1; a <= s; ++a) {
    const double c = quad.c[a];
    qc.col(a) = c <= theta ? VecX(q1 * quad.basis(c / theta)) : VecX(q2 * quad.basis((c - theta) / (1 - theta)));
  }
  qc.col(s) = q2.col(s);
  return total;
}

SolveInfo ContactIntegrator::step(Workspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                  const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                                  Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, Eigen::Ref<VecX> z,
                                  Eigen::Ref<VecX> phi, int& pivots, double& impact) const {
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), s = free_.quadrature().s;
  pivots = 0;
  impact = 0;
  SolveInfo total;
  auto add = [&](const SolveInfo& info) {
    total.status = info.status;
    total.iterations += info.iterations;
    total.factorizations += info.factorizations;
    total.residual_evaluations += info.residual_evaluations;
    total.residual = info.residual;
  };
  bool active = false;  // a contact pushed or rubbed in the step before
  for (int c = 0; c < C; ++c) active = active || z.segment(c * pc, d + 1).cwiseAbs().maxCoeff() > 0;
  bool guessed = false;
  if (!active) {
    add(free_.robust_step(p, u, before_previous, previous, qc, p_next));
    if (total.converged() && free_step_holds(ws, qc, z, phi)) return total;
    guessed = total.converged();  // the free step, through the terrain, is the contact solve's guess
    ws.basis.clear();
    double theta = guessed && locate_ ? impact_time(ws, qc) : 0.0;
    if (theta > 1e-9) {  // split at the impact; if that fails, the plain contact step below
      const MatX free = qc;
      const SolveInfo info = split_step(ws, theta, p, u, qc, p_next, z, phi, pivots);
      total.iterations += info.iterations;
      total.factorizations += info.factorizations;
      total.residual_evaluations += info.residual_evaluations;
      total.status = info.status;
      total.residual = info.residual;
      if (info.converged()) {
        impact = theta;
        return total;
      }
      qc = free;
      z.setZero();
      ws.basis.clear();
    }
  }
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (attempt == 0 && !guessed) {
      if (previous.size() && before_previous.size()) free_.guess_from_history(before_previous, previous, qc);
      else if (previous.size()) free_.guess_from_previous(previous, qc);
      else free_.guess_from_velocity(free_.velocity(qc.col(0), p), qc);
    } else if (attempt > 0) {
      z.setZero();
      ws.basis.clear();
      if (attempt == 1) free_.guess_from_velocity(free_.velocity(qc.col(0), p), qc);
      else qc.rightCols(s).colwise() = VecX(qc.col(0));
    }
    const SolveInfo info = ws.solver.solve(free_.options, tol_, p, u, free_.dt(), qc, z, ws.basis, p_next);
    pivots += ws.solver.lcp_pivots();
    add(info);
    if (info.converged()) {
      phi = ws.solver.gaps();
      return total;
    }
  }
  return total;
}

SolveInfo ContactIntegrator::step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                                  const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc,
                                  Eigen::Ref<VecX> p_next, Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi,
                                  int* pivots, double* impact) const {
  const int n = free_.model().n(), s = free_.quadrature().s;
  check_vector("q", qc.col(0), n);
  check_vector("p", p, n);
  if (z.size() != contacts_.unknowns() || phi.size() != contacts_.size())
    throw InputError("contact step: impulses and gaps of the wrong size");
  if (!z.allFinite()) throw InputError("the impulse guess contains NaN or infinity");
  if (previous.size() && (previous.rows() != n || previous.cols() != s + 1))
    throw InputError("previous control points must have shape (n, s+1)");
  auto ws = pool_.acquire();
  ws->basis.clear();
  int count = 0;
  double theta = 0;
  const SolveInfo info = step(*ws, p, u, MatX(), previous, qc, p_next, z, phi, count, theta);
  if (pivots) *pivots = count;
  if (impact) *impact = theta;
  return info;
}

ContactRollout ContactIntegrator::rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, const VecX& z0,
                                         StepHook* hook) const {
  const Model& model = free_.model();
  const int n = model.n(), s = free_.quadrature().s, S1 = s + 1, m = model.n_controls();
  const int C = contacts_.size(), nz = contacts_.unknowns();
  ContactRollout out;
  free_.start_rollout(q0, p0, N, u, out, hook != nullptr);
  if (z0.size() && (z0.size() != nz || !z0.allFinite() || z0.minCoeff() < 0))
    throw InputError("impulses must be " + std::to_string(nz) + " finite numbers >= 0");
  out.impulses.resize(N, nz);
  out.gaps.resize(N, C);
  out.pivots.resize(N);
  out.impact.setZero(N);
  out.step_p.resize(N + 1, n);
  auto ws = pool_.acquire();
  ws->basis.clear();
  MatX qc(n, S1), prev, prev2, uk(m, S1);
  VecX p = p0, p_next(n), z = z0.size() ? z0 : VecX::Zero(nz), phi(C);
  for (int k = 0; k < N; ++k) {
    qc.col(0) = out.q.row(k).transpose();
    if (hook) {
      free_.hooked_controls(*hook, k, out, p, uk);
    } else if (m > 0) {
      free_.step_controls(u, k, uk);
    }
    int pivots = 0;
    double theta = 0;
    const SolveInfo info = step(*ws, p, uk, prev2, prev, qc, p_next, z, phi, pivots, theta);
    out.impact[k] = theta;
    out.pivots[k] = pivots;
    out.step_p.row(k) = p.transpose();
    free_.record_step(out, k, info, qc, p_next);
    if (!info.converged()) break;
    out.step_p.row(k + 1) = p_next.transpose();
    out.impulses.row(k) = z.transpose();
    if ((k > 0 || z0.size()) && theta == 0)  // ContactRollout's p^k (a split step's impulses act inside it)
      out.p.row(k) += 0.5 * ws->solver.knot_impulse(z).transpose();
    out.gaps.row(k) = phi.transpose();
    p = p_next;
    if (prev.size()) prev2.swap(prev);
    prev = qc;
  }
  return out;
}

}  // namespace hovi
