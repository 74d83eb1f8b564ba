// B independent rollouts, steps or trajectory linearisations in one call, spread over C++
// threads (parallel_for.hpp; threads = 0: thread_count()). Item b is exactly the single call
// (GalerkinIntegrator::rollout, ::step, Linearizer::trajectory_jacobians) on the object
// shared read-only; each call leases its own workspace from the object's pool, so no more
// workspaces exist than threads, and writes only its own result, so the results are those of the
// same calls made one after another, bit for bit, on any number of threads. errors[b] holds the
// message of an exception thrown by item b (empty: none): one bad item does not fail the batch,
// and a solve that fails is a result (its status), not an error.
#pragma once
#include <string>
#include <vector>

#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/integrators/linearizer.hpp"

namespace hovi {

// The initial states of a batch: rows of q (B x n) and of `second` (B x n), momenta p or, when
// `velocities`, velocities q̇ (then p = GalerkinIntegrator::momentum(q, q̇), as a single call takes it).
struct BatchStates {
  const MatX& q;
  const MatX& second;
  bool velocities;
};

struct RolloutBatch {
  std::vector<Rollout> items;
  std::vector<double> seconds;  // time of each item's rollout
  std::vector<std::string> errors;
};

// `steps` steps from each state; u: (B steps) x ((s+1) m), the rows b steps .. (b+1) steps - 1
// item b's controls as rollout takes them (0 columns without controls).
RolloutBatch rollout_batch(const GalerkinIntegrator& integ, const BatchStates& x0, int steps, const MatX& u,
                           int threads = 0);

struct StepBatchItem {
  MatX qc;      // n x (s+1): the control points (the last iterate if the solve failed; a free base: in the
                // chart about q's attitude)
  VecX q_next;  // nq: the end configuration (a free base's public one)
  VecX p_next;
  MatX lambda;  // m_c x s: the multipliers of a constrained model
  VecX z;       // the impulses (contacts)
  ContactReport contact;
  SolveInfo info;
  double seconds = 0;
};

struct StepBatch {
  std::vector<StepBatchItem> items;
  std::vector<std::string> errors;
};

// One step (GalerkinIntegrator::step from an empty history: the velocity guess and its fallbacks,
// multipliers from zero, no impulses active) from each state; u: B x ((s+1) m), row b = vec(u^{0..s}) column-major (m per point).
StepBatch step_batch(const GalerkinIntegrator& integ, const BatchStates& x, const MatX& u, int threads = 0);

// trajectory_jacobians of B trajectories of K steps each: C ((B K) x (s+1) n), U ((B K) x (s+1) m),
// W ((B K) x the steps' other unknowns, or empty: Linearizer::trajectory_jacobians), the rows
// b K .. (b+1) K - 1 item b's; A_k of item b goes to
// As[b K + k] (a (B, K, 2n, 2n) row-major array), B_k to Bs likewise (null: not computed). A
// singular step is item b's error. A free base: the steps' public starts q^k, (B K) x nq, likewise.
std::vector<std::string> trajectory_jacobians_batch(const Linearizer& lin, int B, int K, const MatX& C, const MatX& U,
                                                    const MatX& W, double* As, double* Bs, double smoothing = 0,
                                                    int threads = 0, const MatX& starts = MatX());

}  // namespace hovi
