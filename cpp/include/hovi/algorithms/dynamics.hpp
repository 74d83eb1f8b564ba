// Forward dynamics by the articulated-body algorithm and inverse dynamics by recursive
// Newton-Euler, both in spatial (world-frame) coordinates with gravity entering as the
// external wrench F̄_i of every body; the joint armature adds diag(a) to the mass matrix (ABA: to
// the joint's D_i = S̄_i^T IA_i S̄_i, as Pinocchio does).
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
// q̈ = FD(q, q̇, tau), O(n). Returns data.qdd. Throws ModelError if a joint moves no mass.
const VecX& forward_dynamics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                             const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& tau);
// x = M(q)^{-1} rhs in O(n) by the articulated-body algorithm without bias terms. Returns data.qdd.
const VecX& mass_matrix_solve(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                              const Eigen::Ref<const VecX>& rhs);
// tau = ID(q, q̇, q̈) = M(q) q̈ + C(q, q̇) q̇ + G(q), O(n). Returns data.tau.
const VecX& inverse_dynamics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                             const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& qddot);
}  // namespace hovi
