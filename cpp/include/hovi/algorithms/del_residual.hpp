// Algorithm 1 (Prop. 1): O(sn) evaluation of the discrete Euler-Lagrange equations
//   r^{k,0}   = p^k + D_1 L_d + F_d^{k,0}
//   r^{k,a}   = D_{a+1} L_d + F_d^{k,a},   a = 1..s-1
//   p^{k+1}   = D_{s+1} L_d + F_d^{k,s}
// through the articulated-body momentum μ̄ and impulse Γ̄, with gravity, joint forces
// (springs, dampers, actuation) and body wrenches; work for absent forces is skipped. Joint
// armature, 1/2 a_i q̇_i^2 in K, adds a_i q̇_i^b to the joint momentum S̄_i^b . μ̄_i^b of the
// kinetic term sum_b a^{ab} S̄^b . μ̄^b (it moves no body, so μ̄ and Γ̄ do not carry it).
#pragma once
#include "hovi/algorithms/del_workspace.hpp"

namespace hovi {

// q: n x (s+1) control points q^{k,0..s}; p: p^k; u: m x (s+1) controls at the control
// points (m = model.n_controls()); r: n x s residual (column a = r^{k,a}); p_next: p^{k+1}.
// Fills ws for newton_direction. Sizes are the caller's responsibility (checked in debug).
void del_residual(const Model& model, const Quadrature& quad, DelWorkspace& ws, const Eigen::Ref<const MatX>& q,
                  const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> r,
                  Eigen::Ref<VecX> p_next);

}  // namespace hovi
