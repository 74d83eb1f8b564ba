// The Newton direction of the DEL equations by a dense solve: the Jacobian dr^{k,0..s-1} /
// dq^{k,1..s} (the s n square window of del_jacobian.hpp's Jq, from the linearisation in
// O(s^2 n^2), only those blocks computed) and one LU factorisation, O(s^3 n^3); each further right-hand side costs
// O(s^2 n^2). Below a crossover in n (per s, measured in bench/direction_crossover.py) this is
// cheaper than the recursive O(s^3 n) direction of Algorithms A.1/A.2, whose constant is large.
#pragma once
#include <Eigen/LU>

#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/integrators/direction.hpp"

namespace hovi {

// True when the dense direction is the cheaper one for this model and s: n at most the
// crossover measured per s by bench/direction_crossover.py (factorisation + one solve).
bool dense_direction_is_faster(const Model& model, int s);
// The path a solver with this direction option takes for this model and s.
inline bool uses_dense_direction(Direction direction, const Model& model, int s) {
  return direction == Direction::Dense || (direction == Direction::Auto && dense_direction_is_faster(model, s));
}

// A free base's Newton direction with the chart term's derivative (DenseDirection::factor's r): on the
// dense path at s >= 2, where the direction without it is off by 1e-3 and Newton needs 3.1-3.2
// iterations a step for 2.01; at s = 1 it is off by 3e-5 and the derivative costs more than the
// iteration it saves (bench/README.md, "Free bodies on SE(3)").
inline bool exact_chart_direction(Direction direction, const Model& model, int s) {
  return model.rotation_chart >= 0 && s >= 2 && uses_dense_direction(direction, model, s);
}

class DenseDirection {
 public:
  DenseDirection(const Model& model, const Quadrature& quad);
  // Factors J = dr/dq^{k,1..s} at the control points qc (n x (s+1)) with controls u (m x (s+1)),
  // reusing the forward kinematics of `kinematics` (a del_residual workspace at the same qc and
  // dt) unless null. A free base's chart (with kinematics and the residual r, n x s, at qc): J gains the
  // centre term's derivative, the exact Newton direction (rotation_chart.hpp). Returns false if J is
  // singular to working precision.
  bool factor(const Model& model, const Quadrature& quad, const Eigen::Ref<const MatX>& qc,
              const Eigen::Ref<const MatX>& u, double dt, const DelWorkspace* kinematics = nullptr,
              const MatX* r = nullptr);
  // dq = -J^{-1} r, r and dq n x s (column gamma-1 = δq^{k,gamma}).
  void solve(const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq);
  // X = -J^{-1} R for k right-hand sides at once, R and X (s n) x k (each column a stacked r):
  // one blocked triangular solve in place of k.
  void solve_many(const Eigen::Ref<const MatX>& R, Eigen::Ref<MatX> X);

 private:
  DelJacobianWorkspace ws_;
  MatX J_;                        // (s n) square: the window BlockWindow::newton of the DEL Jacobian
  Eigen::PartialPivLU<MatX> lu_;  // of J_
  VecX x_, y_;  // right-hand side and solution
};

}  // namespace hovi
