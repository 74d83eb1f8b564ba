// Kinetic energy K = 1/2 sum v̄_i^T M̄_i v̄_i + 1/2 sum a_i q̇_i^2 (joint armature) and gravitational potential V = -sum m_i g^T p_i
// (p_i the centre of mass, docs/paper.md C-3/C-4) plus the joint springs' 1/2 k (q - qref)^2.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
double kinetic_energy(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& qdot);
double potential_energy(const Model& model, Data& data, const Eigen::Ref<const VecX>& q);
}  // namespace hovi
