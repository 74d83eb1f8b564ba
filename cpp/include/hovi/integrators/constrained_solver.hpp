// Newton's method on the constrained DEL equations (eq. DEL_general_c) of one step, with the
// multipliers λ^{k,0..s-1} at the control points 0..s-1 and the constraints at 1..s:
//   r^{k,a} + Dh(q^{k,a})^T λ^{k,a} = 0  (a = 0..s-1),   h(q^{k,g}) = 0  (g = 1..s),
//   p^{k+1} = D_{s+1} L_d + F_d^{k,s}.
// The constraint forces are force elements of an augmented model (constraint.hpp), so
// Algorithm 1 evaluates the first equations and the recursive solver factors their Jacobian J
// (λ·d²h included) once per iteration. The KKT system [J C^T; Dh 0] is solved through its Schur
// complement (docs/paper.md A-9): dz_r = -J^{-1} r and W = -J^{-1} C^T by s m + 1 recursive solves
// (O(s^2 n) each), then (Dh W) dλ = -h - Dh dz_r, an (s m) x (s m) dense system; in all
// O(s^3 n + s^3 m n + s^3 m^3) per iteration: O(mn) + O(m^3) for s = 1 as in the paper.
#pragma once
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/integrators/newton_solver.hpp"

namespace hovi {

class ConstrainedSolver {
 public:
  ConstrainedSolver(const Model& model, const Quadrature& quad);

  // qc (n x (s+1)): column 0 = q^k, columns 1..s the guess / solution; lambda (mc x s): guess /
  // solution; u: m x (s+1) user controls; p_next gets p^{k+1}.
  SolveInfo solve(const SolverOptions& opt, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                  double dt, Eigen::Ref<MatX> qc, Eigen::Ref<MatX> lambda, Eigen::Ref<VecX> p_next);

  // The constrained residual (r: n x s with the constraint forces, H: mc x s) and p^{k+1}.
  void evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& lambda,
                double dt, const Eigen::Ref<const MatX>& qc, MatX& r, MatX& H, Eigen::Ref<VecX> p_next);
  // The Newton direction (dz: n x s, dlambda: mc x s) at the state of the last evaluate() with
  // its residual r and constraint values H; false if J or the Schur complement is singular.
  bool direction(double dt, const MatX& r, const MatX& H, MatX& dz, MatX& dlambda);

 private:
  KinematicsView view(int a) const { return KinematicsView{aug_, del_.g.data() + a, del_.Sbar.data() + a, quad_.s + 1}; }

  struct Step;  // the Problem of newton_iterate (constrained_solver.cpp)
  Model aug_;
  const Quadrature& quad_;
  int n_, s_, m_, mc_;
  DelWorkspace del_;
  NewtonWorkspace newton_;
  MatX uaug_, r_, H_, r_trial_, H_trial_, dz_, dlambda_, q_trial_, lambda_trial_, rhs_, W_, S_, Dh_;
  VecX p_trial_, h_, schur_rhs_;
};

}  // namespace hovi
