// The velocity of a constrained model nearest (in the kinetic-energy metric) to a given one
// among those that satisfy the velocity constraint Dh(q) q̇ = 0:
//   q̇ = v - M^{-1} Dh^T (Dh M^{-1} Dh^T)^{-1} Dh v,
// i.e. the solution of [M Dh^T; Dh 0] [q̇; μ] = [M v; 0]. With v = M^{-1} p it reads a
// velocity back from a discrete momentum (the momentum projection of RATTLE-type methods: p is
// defined up to Dh^T μ, which the constraint impulse of the next step absorbs). O(n m + m^3):
// m + 1 articulated-body solves of M, no dense mass matrix.
#pragma once
#include "hovi/model/data.hpp"

namespace hovi {
// v projected onto the tangent space of h(q) = 0. Throws InputError if Dh M^{-1} Dh^T is
// singular (redundant constraints).
VecX tangent_velocity(const Model& model, Data& data, const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& v);
// q̇ from p: tangent_velocity(M(q)^{-1} p) (M(q)^{-1} p without constraints).
VecX velocity_from_momentum(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                            const Eigen::Ref<const VecX>& p);
}  // namespace hovi
