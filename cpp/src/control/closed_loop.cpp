#include "hovi/control/closed_loop.hpp"

#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

namespace hovi {

Rollout closed_loop(const GalerkinIntegrator& plant, const Policy& policy, const std::vector<Push>& pushes,
                    const VecX& q0, const VecX& p0, int N) {
  const Model& model = plant.model();
  policy.check(model, plant.quadrature().s);
  check_pushes(model, pushes);
  PolicyHook hook(model, policy, pushes);
  return plant.rollout(q0, p0, N, MatX(), StepHistory(), &hook);
}

std::vector<std::string> closed_loop_batch(const std::vector<const GalerkinIntegrator*>& plants, const Policy& policy,
                                           const std::vector<std::vector<Push>>& pushes, const MatX& Q0,
                                           const MatX& P0, int N, std::vector<Rollout>& out, int threads) {
  const long B = Q0.rows();
  if (plants.empty() || (plants.size() != 1 && long(plants.size()) != B))
    throw InputError("give one plant, or one per state (" + std::to_string(B) + ")");
  if (pushes.size() > 1 && long(pushes.size()) != B)
    throw InputError("give the pushes of one run, or of each of the " + std::to_string(B) + " runs");
  if (P0.rows() != B) throw InputError("q0 and p0 must have as many rows");
  out.assign(B, Rollout());
  static const std::vector<Push> none;
  return parallel_for(int(B), thread_count(threads), [&](int b, int) {
    const GalerkinIntegrator& plant = *plants[plants.size() == 1 ? 0 : b];
    const std::vector<Push>& push = pushes.empty() ? none : pushes[pushes.size() == 1 ? 0 : b];
    out[b] = closed_loop(plant, policy, push, Q0.row(b).transpose(), P0.row(b).transpose(), N);
  });
}

}  // namespace hovi
