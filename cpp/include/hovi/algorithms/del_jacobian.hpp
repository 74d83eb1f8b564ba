// Section 4: the second derivative of the discrete Lagrangian, D^2 L_d, in O(s^2 n^2) by the
// chain rule through q̇^a = (1/dt) sum_b b^{ab} q^b and the quadrature, from Algorithms 2 and 3
// at each control point; and the Jacobian of the DEL equations (Algorithm 1's outputs) with
// respect to the control points and the controls.
//
// Layouts: block (b, c) of an ((s+1) n) x ((s+1) n) matrix is rows b n..(b+1) n - 1, columns
// c n..(c+1) n - 1.
//   D2Ld(b, c) = d2 L_d / dq^b dq^c
//     = w^b dt (Kqq - Vqq)(b) [b = c] + w^b b^{bc} Kqv(b) + w^c b^{cb} Kvq(c)
//       + sum_a (w^a / dt) b^{ab} b^{ac} Kvv(a).
//   Jq(a, c) = d(row a)/dq^{k,c}, rows a = 0..s-1 the residuals r^{k,a} and row block s the
//     momentum p^{k+1}: D2Ld(a, c) + w^a dt Qq(a) [a = c] + w^a b^{ac} Qv(a).
//   Ju: ((s+1) n) x ((s+1) m), block (a, a) = w^a dt Qu(a): d(row a)/du^{k,a}.
//   d r^{k,0} / dp^k = identity (not stored).
#pragma once
#include <vector>

#include "hovi/algorithms/del_workspace.hpp"
#include "hovi/algorithms/force_jacobians.hpp"
#include "hovi/quadrature/lobatto.hpp"

namespace hovi {

// The block rows row0..row0+rows-1 and block columns col0..col0+cols-1 of that layout (counts
// -1: through block s). A matrix filled through a window is (rows n) x (cols n) and holds those
// blocks only; nothing outside them is computed.
struct BlockWindow {
  int row0 = 0, col0 = 0, rows = -1, cols = -1;
  // The Newton direction's dr^{k,0..s-1} / dq^{k,1..s}.
  static BlockWindow newton(int s) { return {0, 1, s, s}; }
};

struct DelJacobianWorkspace {
  DelJacobianWorkspace(const Model& model, const Quadrature& quad);
  Data data;
  ForceJacobians forces;
  std::vector<MatX> Kvv, Kvq, Kqv, Kqq, Vqq;  // Algorithms 2 and 3 at each control point
  MatX qdot;                                  // n x (s+1)
};

// D^2 L_d (its window) at the control points qc (n x (s+1)). `kinematics`, unless null, is a
// del_residual workspace evaluated at the same qc and dt, whose forward kinematics are reused.
void dlagrangian_hessian(const Model& model, const Quadrature& quad, DelJacobianWorkspace& ws,
                         const Eigen::Ref<const MatX>& qc, double dt, Eigen::Ref<MatX> D2Ld,
                         const DelWorkspace* kinematics = nullptr, BlockWindow window = {});

// Jq (its window) and Ju (all rows, unless null) of the DEL equations at qc with controls u
// (m x (s+1)); `kinematics` as for dlagrangian_hessian.
void del_jacobian(const Model& model, const Quadrature& quad, DelJacobianWorkspace& ws,
                  const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> Jq,
                  MatX* Ju, const DelWorkspace* kinematics = nullptr, BlockWindow window = {});

}  // namespace hovi
