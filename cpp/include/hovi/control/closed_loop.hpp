// Closed-loop runs: a Policy (policy.hpp) in the step loop of a rollout, with its pushes, on a
// plant that may differ from the model the policy was made on (masses, lengths: model mismatch);
// one at a time or B at once on C++ threads (Monte-Carlo studies). The plant is an integrator, with
// or without contacts.
#pragma once
#include <string>
#include <vector>

#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/control/policy.hpp"

namespace hovi {

// N steps of `plant` from (q0, p0) under `policy` (checked against the plant's sizes) with `pushes`.
Rollout closed_loop(const GalerkinIntegrator& plant, const Policy& policy, const std::vector<Push>& pushes,
                    const VecX& q0, const VecX& p0, int N);

// B closed-loop runs: item b on plants[b] (or plants[0] if there is one) from row b of Q0, P0, with
// pushes[b] (or pushes[0], or none if empty), all under one policy. out gets B rollouts; errors[b]
// the message of an exception of item b (empty: none), as batch.hpp.
std::vector<std::string> closed_loop_batch(const std::vector<const GalerkinIntegrator*>& plants, const Policy& policy,
                                           const std::vector<std::vector<Push>>& pushes, const MatX& Q0,
                                           const MatX& P0, int N, std::vector<Rollout>& out, int threads = 0);

}  // namespace hovi
