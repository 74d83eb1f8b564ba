// Algorithm 2 (Prop. 3): the four second-derivative blocks of the kinetic energy in O(n^2),
//   Kvv = d2K/dq̇2,  Kvq[i][j] = d/dq_j (dK/dq̇_i),  Kqv[i][j] = d/dq̇_j (dK/dq_i) = Kvq^T,
//   Kqq = d2K/dq2  (the matrix convention of docs/paper.md, Algorithms 2 and 3). The joint armature's
//   1/2 a_i q̇_i^2 adds diag(a) to Kvv only.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
// Fills data.Kvv, data.Kvq, data.Kqv, data.Kqq.
void kinetic_hessians(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& qdot);
// The same from the kinematics already in data (g, S̄, M̄, v̄ of forward_kinematics with q̇).
void kinetic_hessians(const Model& model, Data& data);
}  // namespace hovi
