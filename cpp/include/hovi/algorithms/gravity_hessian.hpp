// Algorithm 3 (Prop. 4): d2V_g/dq2 of the gravitational potential V_g = -sum m_i g^T p_i
// (p_i the centre of mass) in O(n^2).
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
// Returns data.Vqq.
const MatX& gravity_hessian(const Model& model, Data& data, const Eigen::Ref<const VecX>& q);
// The same from the kinematics already in data (g, S̄ of forward_kinematics).
const MatX& gravity_hessian(const Model& model, Data& data);
}  // namespace hovi
