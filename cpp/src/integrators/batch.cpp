#include "hovi/integrators/batch.hpp"

#include <chrono>
#include <optional>

#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

namespace hovi {

namespace {
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

int checked_batch(const GalerkinIntegrator& integ, const BatchStates& x) {
  const int n = integ.model().n(), nq = integ.model().nq();
  if (x.q.rows() == 0) throw InputError("the batch is empty (B = 0 initial states)");
  if (x.q.cols() != nq || x.second.cols() != n || x.second.rows() != x.q.rows())
    throw InputError("the initial states must be (B, nq) and (B, n) arrays with nq = " + std::to_string(nq) +
                     ", n = " + std::to_string(n));
  return static_cast<int>(x.q.rows());
}

// Item b's momentum, as the single call gets it.
VecX momentum(const GalerkinIntegrator& integ, const BatchStates& x, int b) {
  const VecX q = x.q.row(b).transpose(), v = x.second.row(b).transpose();
  return x.velocities ? integ.momentum(q, v) : v;
}
}  // namespace

RolloutBatch rollout_batch(const GalerkinIntegrator& integ, const BatchStates& x0, int steps, const MatX& u,
                           int threads) {
  const int B = checked_batch(integ, x0);
  threads = thread_count(threads);
  if (steps < 0) throw InputError("the number of steps must be non-negative");
  if (u.cols() && u.rows() != static_cast<Eigen::Index>(B) * steps)
    throw InputError("controls must have B steps = " + std::to_string(B * steps) + " rows");
  RolloutBatch out;
  out.items.resize(B);
  out.seconds.assign(B, 0.0);
  out.errors = parallel_for(B, threads, [&](int b, int) {
    const auto t0 = Clock::now();
    const MatX ub = u.cols() ? MatX(u.middleRows(static_cast<Eigen::Index>(b) * steps, steps)) : MatX(0, 0);
    out.items[b] = integ.rollout(x0.q.row(b).transpose(), momentum(integ, x0, b), steps, ub);
    out.seconds[b] = since(t0);
  });
  return out;
}

StepBatch step_batch(const GalerkinIntegrator& integ, const BatchStates& x, const MatX& u, int threads) {
  const int B = checked_batch(integ, x);
  threads = thread_count(threads);
  const int n = integ.model().n(), S1 = integ.quadrature().s + 1, m = integ.model().n_controls();
  if (u.rows() != B || u.cols() != S1 * m)
    throw InputError("controls must have shape (B, (s+1) m) = (" + std::to_string(B) + ", " + std::to_string(S1 * m) + ")");
  StepBatch out;
  out.items.resize(B);
  out.errors = parallel_for(B, threads, [&](int b, int) {
    const auto t0 = Clock::now();
    StepBatchItem& it = out.items[b];
    VecX p = momentum(integ, x, b);
    const MatX uk = Eigen::Map<const MatX>(MatX(u.row(b)).data(), m, S1);
    it.qc.resize(n, S1);
    it.p_next.resize(n);
    StepHistory h;
    const bool free = integ.model().rotation_chart >= 0;
    std::optional<FreeBase> base;
    if (free) {  // the chart about q's attitude (θ = 0), the momentum in it
      base.emplace(integ.model());
      VecX q0(n);
      base->state_to_chart(x.q.row(b).transpose(), q0, h.centre, p);
      it.qc.col(0) = q0;
    } else {
      it.qc.col(0) = x.q.row(b).transpose();
    }
    it.info = integ.step(p, uk, it.qc, it.p_next, h, &it.contact);
    it.q_next = it.qc.col(S1 - 1);
    if (free) {  // the end state public
      it.q_next.resize(integ.model().nq());
      base->state_to_public(it.qc.col(S1 - 1), h.centre, it.q_next, it.p_next);
    }
    it.lambda = h.lambda;
    it.z = h.z;
    it.seconds = since(t0);
  });
  return out;
}

std::vector<std::string> trajectory_jacobians_batch(const Linearizer& lin, int B, int K, const MatX& C, const MatX& U,
                                                    const MatX& W, double* As, double* Bs, double smoothing, int threads,
                                                    const MatX& starts) {
  if (B < 1) throw InputError("the batch is empty (B = 0 trajectories)");
  threads = thread_count(threads);
  const int n = lin.model().n(), s = lin.quadrature().s, m = lin.model().n_controls();
  const Eigen::Index rows = static_cast<Eigen::Index>(B) * K;
  if (K < 0 || C.rows() != rows || C.cols() != (s + 1) * n || U.rows() != rows || U.cols() != (s + 1) * m ||
      (W.size() && W.rows() != rows) || (starts.size() && starts.rows() != rows))
    throw InputError("control points, controls and the steps' multipliers or impulses must have B K rows");
  const std::size_t a_size = std::size_t(K) * 4 * n * n, b_size = std::size_t(K) * 2 * n * (s + 1) * m;
  return parallel_for(B, threads, [&](int b, int) {
    const Eigen::Index first = static_cast<Eigen::Index>(b) * K;
    const int failed = lin.trajectory_jacobians(C.middleRows(first, K), U.middleRows(first, K),
                                                W.size() ? MatX(W.middleRows(first, K)) : MatX(),
                                                As ? As + b * a_size : nullptr, Bs ? Bs + b * b_size : nullptr, smoothing,
                                                starts.size() ? MatX(starts.middleRows(first, K)) : MatX());
    if (failed >= 0) throw InputError("the DEL Jacobian is singular at step " + std::to_string(failed));
  });
}

}  // namespace hovi
