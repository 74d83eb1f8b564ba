// Baseline for Sec. 5.2 of the paper ("Comparison with Automatic Differentiation"): the DEL
// residual, its Jacobian / Newton direction and D^2 L_d obtained by forward-mode automatic
// differentiation (Eigen's AutoDiffScalar, nested for second derivatives) of the discrete
// Lagrangian
//   L_d(q^0..q^s) = sum_a w^a dt [K(q^a, q̇^a) - V(q^a)],   q̇^a = (1/dt) sum_b b^{ab} q^b,
// written once as scalar-templated forward kinematics in body coordinates (K includes the joint
// armature, 1/2 a_i q̇_i^2). Derivatives are
// taken with respect to all (s+1) n control-point coordinates at once (a generic AD of L_d, no
// use of the tree structure), so the gradient costs O(s^2 n^2) and the Hessian O(s^3 n^3),
// against O(s n), O(s^3 n) and O(s^2 n^2) for Algorithm 1, A.1/A.2 and Sec. 4.
//
// Forces: gravity and the joint springs (1/2 k (q - qref)^2) enter through V; the dampers and
// actuators as the discrete joint forces F^a = w^a dt (-c q̇^a + B u^a) of Assumption 1.
// Body wrenches (model.wrenches) are not supported: the constructor throws ModelError.
// Work arrays are allocated on the first call of each kind and reused; second derivatives are
// computed in chunks of at most 32 Hessian columns per pass (vector-mode strip-mining).
#pragma once
#include <memory>

#include "hovi/model/model.hpp"
#include "hovi/quadrature/lobatto.hpp"

namespace hovi {

class AutodiffDel {
 public:
  AutodiffDel(const Model& model, const Quadrature& quad, double dt);
  ~AutodiffDel();
  AutodiffDel(AutodiffDel&&) noexcept;
  AutodiffDel& operator=(AutodiffDel&&) noexcept;

  int n() const;
  int s() const;
  double dt() const;

  // L_d at the control points qc (n x (s+1)), no derivatives.
  double lagrangian(const MatX& qc);

  // r^0 = p + D_1 L_d + F^0, r^a = D_{a+1} L_d + F^a (a = 1..s-1), p_next = D_{s+1} L_d + F^s,
  // with D L_d by first-order AD over all (s+1) n variables. u: m x (s+1) controls.
  void residual(const MatX& qc, const VecX& p, const MatX& u, MatX& r /* n x s */, VecX& p_next);

  // J = d r^{0..s-1} / d q^{1..s} (sn x sn, block (a, c-1) = d r^a / d q^c) by nested AD over
  // the rows' variables q^{0..s-1} and the columns' q^{1..s}.
  void jacobian(const MatX& qc, const MatX& u, MatX& J);

  // dq = -J^{-1} r (n x s, column c-1 = δq^c) by a dense LU; r from the same nested AD pass.
  void newton_direction(const MatX& qc, const VecX& p, const MatX& u, MatX& dq);

  // D^2 L_d ((s+1) n square, block (b, c) = d^2 L_d / dq^b dq^c) by nested AD. L_d includes the
  // springs' potential, so this is hovi's dlagrangian_hessian (which counts springs among the
  // joint forces Q) plus the block diagonal -w^b dt k_i.
  void d2Ld(const MatX& qc, MatX& H);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hovi
