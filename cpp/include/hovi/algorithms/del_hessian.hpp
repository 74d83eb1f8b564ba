// The second derivatives of one step's DEL equations contracted with multipliers: the Hessian of
//   nu . [D L_d + F_d] = D L_d[nu] + sum_a w^a dt nu^a . Q(q^a, q̇^a, u^a)
// (nu: n x (s+1), column a multiplying the rows of D_{a+1} L_d + F_d^{k,a}, del_jacobian.hpp's
// layout) with respect to the control points q^{k,0..s} and the inputs u^{k,0..s}.
//   L_d part: the third derivative of L_d along nu is the derivative of D^2 L_d along nu,
//     d/de D^2 L_d(q + e nu): a central difference of Section 4's D^2 L_d (two evaluations per
//     step, whatever n), with e = eps^(1/3) max(1, |q|_inf) / |nu|_inf.
//   Forcing part: only body wrenches have second derivatives (joint forces are linear in q, q̇,
//     u). A constant world force f at a body point scaled by a control u_c (BodyWrench::
//     world_point_force: contact forces) is the gradient of u_c f . x(q), so nu . Q has the
//     q-Hessian u_c d/de H_f(q + e nu) with H_f = d(J^T f)/dq (body_points.hpp): one central
//     difference of H_f per control point for all of them, and the (u_c, q) block H_f^T nu.
//     The others: per control point, central differences of the gradient (Q_q^T nu^a, Q_v^T nu^a,
//     Q_u^T nu^a) along each of q, and of q̇ and u unless every wrench is free of q̇ / affine in
//     u (BodyWrench::velocity_free, control_affine: their rows then come by symmetry), and only
//     for the joints on the paths from the wrenches' bodies to the root (the others move none),
//     chained through q̇^a = (1/dt) sum_c b^{ac} q^c.
// Both are symmetrised. Accuracy: the differences' O(e^2) and round-off, about 1e-9 relative
// (tests/test_trajopt_program.py checks it against differences of the exact Jacobian).
#pragma once
#include <vector>

#include "hovi/algorithms/del_jacobian.hpp"

namespace hovi {

struct DelHessianWorkspace {
  DelHessianWorkspace(const Model& model, const Quadrature& quad);
  struct PointForce {
    int body;
    Vec3 point, force;   // the point in the body's COM frame
    int control;         // -1: none
  };
  DelJacobianWorkspace jac;
  ForceJacobians forces;
  std::vector<PointForce> point_forces;   // the world point forces (exact)
  Model differenced;                      // the model with only the other wrenches (differenced)
  Data kin_p, kin_m;                      // the kinematics at q^a +- e nu^a
  MatX D2p, D2m, qp, Hphi, Gp, Tp, Tm, Hf;   // scratch
  VecX z, gp, gm, d;
  std::vector<int> moving;   // the joints that move some differenced wrench's body (Model::joints_moving)
};

// Hqq ((s+1) n square), Huq ((s+1) m x (s+1) n, block a: rows of u^a) and Huu ((s+1) m square,
// block diagonal) of nu . [D L_d + F_d] at control points qc (n x (s+1)) and inputs u (m x (s+1),
// m = model.n_controls()). All three are overwritten.
void del_hessian(const Model& model, const Quadrature& quad, DelHessianWorkspace& ws, const Eigen::Ref<const MatX>& qc,
                 const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& nu, double dt, Eigen::Ref<MatX> Hqq,
                 Eigen::Ref<MatX> Huq, Eigen::Ref<MatX> Huu);

}  // namespace hovi
