// GalerkinIntegrator::rollout: the loop over steps (galerkin_integrator.hpp) and its record.
#include <cmath>
#include <string>

#include "hovi/integrators/galerkin_integrator.hpp"

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/dense_direction.hpp"

namespace hovi {

void GalerkinIntegrator::start_rollout(const VecX& q0, const VecX& p0, int N, const MatX& u,
                                       const StepHistory& start, Rollout& out, bool hooked) const {
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls();
  check_vector("q0", q0, model_.nq());
  check_vector("p0", p0, n);
  if (N < 0) throw InputError("the number of steps must be non-negative");
  if (hooked) out.controls.setZero(N, S1 * m);
  if (m > 0 && !hooked && (u.rows() != N || u.cols() != S1 * m))
    throw InputError("controls must have shape (steps, s+1, m) = (" + std::to_string(N) + ", " + std::to_string(S1) +
                     ", " + std::to_string(m) + ")");
  if (m > 0 && !hooked && !u.allFinite()) throw InputError("controls contain NaN or infinity");
  if (start.previous.size() && (start.previous.rows() != n || start.previous.cols() != S1))
    throw InputError("previous control points must have shape (n, s+1)");
  if (start.z.size()) check_impulses(start.z);
  out.q.resize(N + 1, n);
  out.p.resize(N + 1, n);
  out.control_points.resize(N, S1 * n);
  out.multipliers.resize(N, s * model_.n_constraints());
  out.iterations.resize(N);
  out.factorizations.resize(N);
  out.residual.resize(N);
  out.status.reserve(N);
  out.q.row(0) = q0.head(n).transpose();  // a free base: set by rollout
  out.p.row(0) = p0.transpose();
  if (!has_contacts()) return;
  out.contact.impulses.resize(N, contacts_.unknowns());
  out.contact.gaps.resize(N, contacts_.size());
  out.contact.pivots.resize(N);
  out.contact.impact.setZero(N);
  out.contact.step_p.resize(N + 1, n);
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

Rollout GalerkinIntegrator::rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, StepHistory h,
                                    StepHook* hook) const {
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), mc = model_.n_constraints();
  Rollout out;
  start_rollout(q0, p0, N, u, h, out, hook != nullptr);
  MatX attitude;  // a free base: (N+1) x 4, the base's attitude at q^k
  if (free_base_) {
    VecX q(n), p(p0);
    free_base_->state_to_chart(q0, q, h.centre, p);
    out.q.row(0) = q.transpose();
    out.p.row(0) = p.transpose();
    attitude.resize(N + 1, 4);
    attitude.row(0) = rotation_quaternion(h.centre).transpose();
  }
  const bool continued = h.z.size() > 0;  // a contact rollout continuing another (its first knot's impulse known)
  h.lambda = lambda_guess(h.lambda.size() ? &h.lambda : nullptr);
  if (!continued) h.z = VecX::Zero(contacts_.unknowns());
  auto ws = pool_.acquire();
  MatX qc(n, S1), uk(m, S1);
  VecX p = out.p.row(0).transpose(), p_next(n);
  ContactReport report;
  PredictorChoice predictor(options.predictor, s, uses_dense_direction(options.direction, model_, s));
  for (int k = 0; k < N; ++k) {
    qc.col(0) = out.q.row(k).transpose();
    if (hook) {  // the hook's controls (and its momentum: an impulse) into uk and the record
      uk.setZero(m, S1);
      const bool controlled = free_base_ ? public_hook(*hook, k, qc.col(0), h.centre, p, uk)
                                         : hook->before_step(k, out.q.row(k).transpose(), p, uk);
      if (uk.rows() != m || uk.cols() != S1 || !p.allFinite())
        throw InputError("the controller gave controls of the wrong shape, or a momentum with NaN or infinity, at "
                         "step " + std::to_string(k));
      // no controls for this state (none, or not finite ones: an overflowing feedback): the run ends here
      if (!controlled || !uk.allFinite()) {
        SolveInfo stopped;
        stopped.status = SolveStatus::ControllerFailed;
        stopped.residual = NAN;
        record_step(out, k, stopped, qc, p_next);
        break;
      }
      out.p.row(k) = p.transpose();
      out.controls.row(k) = Eigen::Map<const VecX>(uk.data(), uk.size()).transpose();
    } else {
      for (int a = 0; a < S1; ++a)
        for (int j = 0; j < m; ++j) uk(j, a) = u(k, a * m + j);
    }
    // The flow predictor serves the free steps of models without contacts (PredictorChoice).
    const bool predicted = h.before_previous.size() > 0 && !has_contacts();
    const bool flow = predicted && predictor.flow();
    const SolveInfo info = step(*ws, p, uk, qc, p_next, h, report, flow);
    if (predicted) predictor.observe(flow, info.iterations);
    if (free_base_) {  // q^k and p^k in the chart the step re-centred at q^k's attitude
      p = ws->p_chart;
      out.q.row(k) = qc.col(0).transpose();
      out.p.row(k) = p.transpose();
      if (info.converged())
        attitude.row(k + 1) =
            rotation_quaternion(h.centre * free_base_->chart.rotation(qc.col(s).segment<3>(model_.rotation_chart)))
                .transpose();
    }
    if (has_contacts()) {
      out.contact.impact[k] = report.impact;
      out.contact.pivots[k] = report.pivots;
      out.contact.step_p.row(k) = p.transpose();
    }
    record_step(out, k, info, qc, p_next);
    if (!info.converged()) break;
    if (mc) out.multipliers.row(k) = Eigen::Map<const VecX>(h.lambda.data(), h.lambda.size()).transpose();
    if (has_contacts()) {
      out.contact.step_p.row(k + 1) = p_next.transpose();
      out.contact.impulses.row(k) = h.z.transpose();
      if ((k > 0 || continued) && report.impact == 0)  // p^k with half its knot's impulse (a split step's act inside it)
        out.p.row(k) += 0.5 * ws->contact->knot_impulse(h.z).transpose();
      out.contact.gaps.row(k) = report.phi.transpose();
    }
    p = p_next;
    if (h.previous.size()) h.before_previous.swap(h.previous);
    h.previous = qc;
  }
  if (free_base_) public_record(out, attitude);
  return out;
}

bool GalerkinIntegrator::public_hook(StepHook& hook, int k, const VecX& q, const Mat3& centre, VecX& p,
                                     MatX& uk) const {
  VecX q_pub(model_.nq());
  free_base_->state_to_public(q, centre, q_pub, p);
  const bool controlled = hook.before_step(k, q_pub, p, uk);
  if (p.allFinite())
    free_base_->momentum_to_chart(q, centre * free_base_->chart.rotation(q.segment<3>(model_.rotation_chart)), p);
  return controlled;
}

void GalerkinIntegrator::public_record(Rollout& out, const MatX& attitude) const {
  const int n = model_.n(), j = model_.rotation_chart;
  MatX q(out.q.rows(), model_.nq());
  Eigen::Vector4d last = attitude.row(0).transpose();
  for (int k = 0; k <= out.steps; ++k) {
    Eigen::Vector4d quat = attitude.row(k).transpose();
    if (quat.dot(last) < 0) quat = -quat;  // the sign that keeps the quaternion continuous in time
    last = quat;
    const VecX qk = out.q.row(k).transpose();
    q.row(k) << qk.head(j).transpose(), quat.transpose(), qk.tail(n - j - 3).transpose();
    const Mat3 R = quaternion_rotation(quat);
    VecX x = out.p.row(k).transpose();
    free_base_->momentum_to_public(qk, R, x);
    out.p.row(k) = x.transpose();
    if (out.contact.step_p.rows() > k) {
      x = out.contact.step_p.row(k).transpose();
      free_base_->momentum_to_public(qk, R, x);
      out.contact.step_p.row(k) = x.transpose();
    }
  }
  out.q.swap(q);
}

}  // namespace hovi
