// The generalized non-conservative force Q(q, q̇, u) = (joint forces) + sum_b J_b(q)^T F̄_b over
// the body wrench elements (gravity is not included: the linearisation takes it through V_g,
// Algorithm 3) and its Jacobians dQ/dq, dQ/dq̇, dQ/du. For a wrench on body b,
//   Q_j = S̄_j^T F̄_b for j on the path from b to the root, and for l on that path
//   dQ_j/dq_l = S̄_j^T ([l ∈ anc(j) ∪ {j}] ad^D_F̄ S̄_l + D_1F̄ S̄_l + D_2F̄ ad_{S̄_l}(v̄_b - v̄_par(l))),
//   dQ_j/dq̇_l = S̄_j^T D_2F̄ S̄_l,   dQ_j/du = S̄_j^T D_uF̄.
// Cost O(n + sum over elements of depth^2); joint forces are diagonal. Work for absent kinds of
// force is skipped.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {

struct ForceJacobians {
  explicit ForceJacobians(const Model& model);
  VecX Q;          // generalized force
  MatX Qq, Qv, Qu; // n x n, n x n, n x m
};

// with_u = false skips dQ/du.
void force_jacobians(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                     const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& u, ForceJacobians& out,
                     bool with_u = true);

}  // namespace hovi
