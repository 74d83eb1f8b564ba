#include "hovi/control/closed_loop.hpp"

#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

namespace hovi {
namespace {

const GalerkinIntegrator& free_integrator(const GalerkinIntegrator& plant) { return plant; }
const GalerkinIntegrator& free_integrator(const ContactIntegrator& plant) { return plant.integrator(); }

Rollout run(const GalerkinIntegrator& plant, PolicyHook& hook, const VecX& q0, const VecX& p0, int N) {
  return plant.rollout(q0, p0, N, MatX(), MatX(), MatX(), &hook);
}
ContactRollout run(const ContactIntegrator& plant, PolicyHook& hook, const VecX& q0, const VecX& p0, int N) {
  return plant.rollout(q0, p0, N, MatX(), VecX(), &hook);
}

template <class Plant>
auto closed_loop_run(const Plant& plant, const Policy& policy, const std::vector<Push>& pushes, const VecX& q0,
                     const VecX& p0, int N) {
  const GalerkinIntegrator& integ = free_integrator(plant);
  const Model& model = integ.model();
  policy.check(model.n(), model.n_controls(), integ.quadrature().s);
  check_pushes(model, pushes);
  PolicyHook hook(model, policy, pushes);
  return run(plant, hook, q0, p0, N);
}

}  // namespace

Rollout closed_loop(const GalerkinIntegrator& plant, const Policy& policy, const std::vector<Push>& pushes,
                    const VecX& q0, const VecX& p0, int N) {
  return closed_loop_run(plant, policy, pushes, q0, p0, N);
}

ContactRollout closed_loop(const ContactIntegrator& plant, const Policy& policy, const std::vector<Push>& pushes,
                           const VecX& q0, const VecX& p0, int N) {
  return closed_loop_run(plant, policy, pushes, q0, p0, N);
}

template <class Plant, class Result>
std::vector<std::string> closed_loop_batch(const std::vector<const Plant*>& plants, const Policy& policy,
                                           const std::vector<std::vector<Push>>& pushes, const MatX& Q0,
                                           const MatX& P0, int N, std::vector<Result>& out, int threads) {
  const long B = Q0.rows();
  if (plants.empty() || (plants.size() != 1 && long(plants.size()) != B))
    throw InputError("give one plant, or one per state (" + std::to_string(B) + ")");
  if (pushes.size() > 1 && long(pushes.size()) != B)
    throw InputError("give the pushes of one run, or of each of the " + std::to_string(B) + " runs");
  if (P0.rows() != B) throw InputError("q0 and p0 must have as many rows");
  out.assign(B, Result());
  static const std::vector<Push> none;
  return parallel_for(int(B), thread_count(threads), [&](int b, int) {
    const Plant& plant = *plants[plants.size() == 1 ? 0 : b];
    const std::vector<Push>& push = pushes.empty() ? none : pushes[pushes.size() == 1 ? 0 : b];
    out[b] = closed_loop(plant, policy, push, Q0.row(b).transpose(), P0.row(b).transpose(), N);
  });
}

template std::vector<std::string> closed_loop_batch<GalerkinIntegrator, Rollout>(
    const std::vector<const GalerkinIntegrator*>&, const Policy&, const std::vector<std::vector<Push>>&, const MatX&,
    const MatX&, int, std::vector<Rollout>&, int);
template std::vector<std::string> closed_loop_batch<ContactIntegrator, ContactRollout>(
    const std::vector<const ContactIntegrator*>&, const Policy&, const std::vector<std::vector<Push>>&, const MatX&,
    const MatX&, int, std::vector<ContactRollout>&, int);

}  // namespace hovi
