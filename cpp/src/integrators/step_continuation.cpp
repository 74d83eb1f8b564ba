#include "hovi/integrators/step_continuation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/algorithms/tangent_velocity.hpp"
#include "hovi/errors.hpp"

namespace hovi {

namespace {

double inf_norm(const Eigen::Ref<const MatX>& x) { return x.size() ? x.cwiseAbs().maxCoeff() : 0.0; }

// The part of the first continuation step that is only a probe: a step this small (relative to
// dt) lies deep inside the region where the DEL solution near q^k is unique (it is O(h^2) away
// from the predictor q^k + c^a h q̇^k), and its only purpose is the curvature of the branch at
// h = 0 for the quadratic predictor of the next step.
constexpr double kProbe = 0.01;

enum class Corrector { Converged, Rejected };

// The corrector: undamped Newton on the DEL equations (eq. DEL_general1-2) at the fixed step
// length h, from the predictor in qc, with the exact direction of Algorithms 1, A.1 and A.2.
// Undamped on purpose: a line search is a globalisation, and a corrector that needs one has left
// the neighbourhood of the branch. It is rejected unless every Newton correction contracts by
// max_contraction (Deuflhard's monitor of the Newton-Kantorovich ball: the iterates then stay
// within ||δq_0|| / (1 - θ) of the predictor, so they converge to the root nearest to it).
// A Problem of newton_iterate (newton_driver.hpp).
struct CorrectorStep {
  NewtonSolver& solver;
  ContinuationWorkspace& ws;
  const Model& model;
  const Quadrature& quad;
  const ContinuationOptions& copt;
  const Eigen::Ref<const VecX>& p;
  const Eigen::Ref<const MatX>& u;
  double h;
  Eigen::Ref<MatX>& qc;
  Eigen::Ref<VecX>& p_next;

  void evaluate() { del_residual(model, quad, solver.del, qc, p, u, h, ws.r, p_next); }  // Algorithm 1
  double residual_norm() const { return inf_norm(ws.r); }
  double stationarity() const { return inf_norm(ws.r); }
  bool finite() const { return ws.r.allFinite() && p_next.allFinite(); }  // else h too long: shorten it
  bool feasible() const { return true; }
  double iterate_norm() const { return inf_norm(qc); }
  bool has_factor() const { return false; }
  Factor factor() { return newton_factor(model, quad, solver.del, solver.newton) ? Factor::Ok : Factor::Singular; }
  void direction() { newton_solve(model, quad, solver.del, solver.newton, ws.r, ws.dq); }  // δq = -J^{-1} r
  bool direction_finite() const { return ws.dq.allFinite(); }
  double correction_norm() const { return inf_norm(ws.dq); }
  bool accept_direction(double dq, double previous) const { return !(dq > copt.max_contraction * previous); }
  void trial(double) {
    qc.rightCols(quad.s) += ws.dq;
    evaluate();
  }
  bool sufficient_decrease(double) const { return true; }
  void commit() const {}
  int restore() const { return 0; }
};

Corrector correct(NewtonSolver& solver, ContinuationWorkspace& ws, const Model& model, const Quadrature& quad,
                  const StoppingRule& rule, const ContinuationOptions& copt, const Eigen::Ref<const VecX>& p,
                  const Eigen::Ref<const MatX>& u, double h, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                  SolveInfo& info) {
  CorrectorStep step{solver, ws, model, quad, copt, p, u, h, qc, p_next};
  step.evaluate();
  NewtonLoop loop;
  loop.max_iterations = copt.max_corrector_iterations;
  loop.line_search = false;
  loop.estimate_from_contraction = false;
  const SolveInfo c = newton_iterate(step, rule, loop);
  info.iterations += c.iterations;
  info.factorizations += c.factorizations;
  info.residual_evaluations += c.residual_evaluations;
  return c.converged() ? Corrector::Converged : Corrector::Rejected;
}

}  // namespace

int jacobian_determinant_sign(const NewtonWorkspace& factor) {
  // Algorithm A.2 eliminates the bodies from the leaves to the root, one s x s pivot Λ_i each, so
  // det J = Π_i det Λ_i (= Π_i 1 / det Λ̄_i) up to the ordering of rows and columns, the one of
  // J's blocks (rows r^{k,0..s-1}, columns q^{k,1..s}); checked against a dense J in the tests.
  int sign = 1;
  for (const MatX& Linv : factor.Lambda_inv)
    if (Linv.determinant() < 0) sign = -sign;
  return sign;
}

int small_step_determinant_sign(const Quadrature& quad, int n) {
  // As h -> 0 the kinetic term of D^2 L_d dominates (eq. ddl with q̇^a from eq. qdot):
  // J(a, c) -> (1/h) Σ_α w^α b^{αa} b^{αc} M(q^k), rows a = 0..s-1, columns c = 1..s, so
  // det J -> h^{-sn} det(K)^n det(M)^s with det M > 0.
  const int s = quad.s;
  MatX K(s, s);
  for (int a = 0; a < s; ++a)
    for (int c = 1; c <= s; ++c) {
      double k = 0;
      for (int al = 0; al <= s; ++al) k += quad.w[al] * quad.b(al, a) * quad.b(al, c);
      K(a, c - 1) = k;
    }
  const double d = K.determinant();
  return (d < 0 && n % 2 == 1) ? -1 : 1;
}

ContinuationWorkspace::ContinuationWorkspace(const Model& model, const Quadrature& quad)
    : del_h(model, quad), data(model), q_prev(model.n(), quad.s + 1), q_pred(model.n(), quad.s + 1),
      tangent(model.n(), quad.s + 1), r(model.n(), quad.s), r_plus(model.n(), quad.s), r_minus(model.n(), quad.s),
      dq(model.n(), quad.s), p_scratch(model.n()) {}

SolveInfo step_continuation(NewtonSolver& solver, const Model& model, const Quadrature& quad,
                            const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                            const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                            const ContinuationOptions& copt, ContinuationReport* report) {
  ContinuationWorkspace ws(model, quad);
  return step_continuation(solver, ws, model, quad, opt, p, u, dt, qc, p_next, copt, report);
}

SolveInfo step_continuation(NewtonSolver& solver, ContinuationWorkspace& ws, const Model& model,
                            const Quadrature& quad, const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                            const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                            const ContinuationOptions& copt, ContinuationReport* report) {
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite");
  if (!(copt.min_increment > 0) || !(copt.first_increment > 0) || !(copt.max_contraction > 0) ||
      !(copt.max_displacement > 0) || !(copt.max_tangent_mismatch > 0) || copt.max_corrector_iterations < 1 ||
      copt.max_iterations < 1)
    throw InputError("invalid continuation options");
  if (model.n_constraints()) throw InputError("step_continuation solves the DEL equations without constraints");
  const int s = quad.s;
  const StoppingRule rule = stopping_rule(opt, p);
  SolveInfo info;
  ContinuationReport rep;
  auto finish = [&](SolveStatus status) {
    info.status = status;
    if (report) *report = rep;
    return info;
  };
  if (!p.allFinite() || !qc.col(0).allFinite() || !u.allFinite()) {
    info.residual = std::numeric_limits<double>::infinity();
    return finish(SolveStatus::NonFinite);
  }
  const VecX q0 = qc.col(0);

  // The branch at h = 0 (eq. qdot with q^{k,a} -> q^k): q^{k,a}(h) = q^k + c^a h q̇^k + O(h^2),
  // q̇^k = M(q^k)^{-1} p^k, the velocity whose momentum of eq. DEL_general1 is p^k as h -> 0.
  const VecX qdot0 = velocity_from_momentum(model, ws.data, q0, p);
  double h = 0;                                          // the last point (h, q_prev) on the branch
  ws.q_prev.colwise() = q0;
  for (int a = 0; a <= s; ++a) ws.tangent.col(a) = quad.c[a] * qdot0;  // dq^{k,a}/dh there
  MatX q_back;                                           // the point before, for the quadratic predictor
  double h_back = 0;
  bool have_back = false;
  // On the branch, det J keeps the sign it has as h -> 0 (it vanishes at a fold, where the branch
  // turns back in h): a root with the other sign lies beyond an odd number of folds.
  const int sign0 = small_step_determinant_sign(quad, model.n());

  double increment = std::min(kProbe, copt.first_increment) * dt;  // the probe first
  bool probe = true, out_of_budget = false;
  while (true) {
    if (info.iterations >= copt.max_iterations) {
      qc = ws.q_prev;
      out_of_budget = true;  // reported as MaxIterations below
      break;
    }
    // 1. Predictor: a Taylor step along the tangent dq/dh at (h, q_prev), with the curvature of
    //    the branch from the point before (the quadratic through (h_back, q_back) that has value
    //    and slope of the branch at h), q_pred = q + d t + d^2 C.
    const double h_new = std::min(h + increment, dt);
    const double d = h_new - h;
    ws.q_pred = ws.q_prev + d * ws.tangent;
    if (have_back) {
      const double e = h - h_back;
      ws.q_pred += (d * d / (e * e)) * (q_back - ws.q_prev + e * ws.tangent);
    }
    ws.q_pred.col(0) = q0;
    qc = ws.q_pred;

    // 2. Corrector at h_new (DEL equations with p^k fixed, eq. DEL_general1-2).
    const int iterations_before = info.iterations;
    bool accepted = correct(solver, ws, model, quad, rule, copt, p, u, h_new, qc, p_next, info) ==
                    Corrector::Converged;
    const int corrector_iterations = info.iterations - iterations_before;
    // 3. The root must be the one the predictor aimed at: the corrector moved it by at most a
    //    fraction of the predicted step (not for the probe, whose predictor is exact to O(h^2)
    //    only, which is all of the step when q̇^k = 0).
    if (accepted && !probe &&
        inf_norm(qc - ws.q_pred) > copt.max_displacement * inf_norm(ws.q_pred - ws.q_prev))
      accepted = false;
    // 4. Fold parity: factor J at the root (Algorithm A.2) and compare the sign of det J.
    if (accepted) {
      del_residual(model, quad, solver.del, qc, p, u, h_new, ws.r, p_next);
      ++info.residual_evaluations;
      accepted = newton_factor(model, quad, solver.del, solver.newton);
      ++info.factorizations;
      if (accepted && jacobian_determinant_sign(solver.newton) != sign0) {
        accepted = false;
        ++rep.fold_parity_rejections;
      }
    }
    // 5. The tangent at the new root, J dq/dh = -∂r/∂h (∂r/∂h by central differences of Algorithm
    //    1 in h, with the factorisation of step 4), and the consistency of the step with the two
    //    tangents: q_new - q_prev = d (t_prev + t_new) / 2 + O(d^3) on a smooth branch; a root on
    //    another sheet, or a step across a fold, breaks it.
    if (accepted) {
      const double eps = 1e-6 * h_new;
      del_residual(model, quad, ws.del_h, qc, p, u, h_new + eps, ws.r_plus, ws.p_scratch);
      del_residual(model, quad, ws.del_h, qc, p, u, h_new - eps, ws.r_minus, ws.p_scratch);
      info.residual_evaluations += 2;
      ws.r = (ws.r_plus - ws.r_minus) / (2 * eps);
      newton_solve(model, quad, solver.del, solver.newton, ws.r, ws.dq);  // -J^{-1} ∂r/∂h = dq/dh
      accepted = ws.dq.allFinite();
      if (accepted && !probe) {
        const double step = inf_norm(qc - ws.q_prev);
        ws.q_pred.rightCols(s) = qc.rightCols(s) - ws.q_prev.rightCols(s) -
                                 (0.5 * d) * (ws.tangent.rightCols(s) + ws.dq);  // (scratch)
        accepted = inf_norm(ws.q_pred.rightCols(s)) <= copt.max_tangent_mismatch * step;
      }
    }

    if (accepted) {
      // 6. Accept: shift the points; lengthen the increment when the corrector was quick (x2 for
      //    at most 2 iterations, x1.25 for 3-4), keep it otherwise.
      q_back = ws.q_prev;
      h_back = h;
      have_back = true;
      ws.q_prev = qc;
      ws.tangent.col(0).setZero();
      ws.tangent.rightCols(s) = ws.dq;
      h = h_new;
      ++rep.steps;
      rep.h_reached = h;
      if (h >= dt) break;
      if (probe) {
        probe = false;
        increment = std::min(copt.first_increment * dt, dt - h);  // then try the rest at once
      } else if (corrector_iterations <= 2) {
        increment *= 2;
      } else if (corrector_iterations <= 4) {
        increment *= 1.25;
      }
    } else {
      // Rejected: back to the last point of the branch with half the increment. An increment
      // that shrinks below min_increment dt means that the branch does not continue past h
      // (a fold: the solution runs off as dq/dh ~ (h* - h)^{-1/2} while J turns singular).
      ++rep.rejected;
      qc = ws.q_prev;
      increment *= 0.5;
      if (increment < copt.min_increment * dt) break;
    }
  }

  if (h >= dt) {
    // 7. The root at dt: finish with NewtonSolver's own stopping rule (it returns at once when
    //    the residual already meets opt.tol; otherwise a few corrections from a root-close point).
    const SolveInfo last = solver.solve(model, quad, opt, p, u, dt, qc, p_next);
    info.iterations += last.iterations;
    info.factorizations += last.factorizations;
    info.residual_evaluations += last.residual_evaluations;
    info.residual = last.residual;
    return finish(last.status);
  }
  // Failure: qc holds the last point of the branch (at h_reached < dt); the residual reported is
  // that of the DEL equations at dt there.
  del_residual(model, quad, solver.del, qc, p, u, dt, ws.r, p_next);
  ++info.residual_evaluations;
  info.residual = inf_norm(ws.r);
  return finish(out_of_budget ? SolveStatus::MaxIterations : SolveStatus::ContinuationStalled);
}

}  // namespace hovi
