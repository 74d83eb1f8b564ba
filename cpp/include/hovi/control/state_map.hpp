// The integrator's state x = (q, p) against the user's (q, q̇): q̇ = M(q)^{-1} p (p = dL/dq̇), so
//   d(q, q̇)/d(q, p) = [[I, 0], [-M^{-1} dp/dq|_q̇, M^{-1}]],  dp/dq|_q̇ = Kvq (kinetic_hessians.hpp),
// which turns a cost on (q, q̇) into one on (q, p): Q_x = T^T Q T.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {

// T = d(q, q̇)/d(q, p) (2n x 2n) at (q, p); models without holonomic constraints. A free base: q public
// (nq), p and q̇ = v its public momentum and velocity, and q's derivative a tangent δ (q ⊕ δ).
void velocity_state_map(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                        const Eigen::Ref<const VecX>& p, MatX& T);

}  // namespace hovi
