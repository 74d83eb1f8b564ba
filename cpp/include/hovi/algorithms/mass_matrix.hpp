// Joint-space mass matrix by composite rigid bodies in spatial coordinates:
// M[i][j] = S̄_j^T (sum of M̄ over the subtree of i) S̄_i for j in anc(i) ∪ {i}, plus the joint
// armature on the diagonal.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
// Returns data.Mq.
const MatX& mass_matrix(const Model& model, Data& data, const Eigen::Ref<const VecX>& q);
}  // namespace hovi
