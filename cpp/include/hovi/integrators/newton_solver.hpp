// Newton's method on the DEL equations of one step, with the exact O(s^3 n) direction
// (Algorithms 1, A.1, A.2) and a backtracking line search. A damped step x + λ dx is accepted
// when it decreases the residual norm (Armijo) or passes Deuflhard's natural monotonicity test
// ||J(x)^{-1} r(x + λ dx)|| <= (1 - λ/4) ||dx||, which is affine invariant and escapes the false
// minima of ||r|| that stall a pure residual-norm search at large steps; the simplified
// correction costs one more O(s^2 n) recursive solve with the factorisation at x.
#pragma once
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/newton_direction.hpp"

namespace hovi {

struct SolverOptions {
  double tol = 1e-10;        // converged when ||r||_inf <= tol * (1 + ||p^k||_inf), or when the
                             // Newton step falls below round-off, 1e-14 (1 + ||q||_inf)
  int max_iterations = 30;
  int max_backtracks = 12;   // halvings of the step before the line search gives up
  bool line_search = true;   // false: always take the full Newton step
  double constraint_tol = 1e-12;  // constrained steps: also ||h(q^{k,1..s})||_inf <= this
  // Simplified Newton (opt-in): keep the factorisation of the DEL Jacobian (Algorithm A.2's
  // residual-independent part) across iterations and steps while the iteration contracts fast
  // (||dq_k|| <= 0.25 ||dq_{k-1}||) and full steps are accepted; refactor otherwise. Each reuse
  // costs an O(s^2 n) solve instead of an O(s^3 n) factorisation. Off by default: the linear
  // convergence stops just below tol, and over long runs that solver error shows as a slow
  // energy drift that exact Newton (quadratic, landing far below tol) does not have.
  bool reuse_jacobian = false;
};

enum class SolveStatus { Converged, MaxIterations, LineSearchFailed, SingularJacobian, NonFinite };
const char* to_string(SolveStatus status);

struct SolveInfo {
  SolveStatus status = SolveStatus::MaxIterations;
  int iterations = 0;        // Newton directions computed
  int factorizations = 0;    // of them, those that refactored the Jacobian (the rest reused one)
  int residual_evaluations = 0;
  double residual = 0;       // ||r||_inf at exit
  bool converged() const { return status == SolveStatus::Converged; }
};

class NewtonSolver {
 public:
  NewtonSolver(const Model& model, const Quadrature& quad);
  // Solves r(q^{k,0..s}) = 0 for q^{k,1..s}. qc (n x (s+1)): column 0 is q^k, columns 1..s the
  // initial guess on entry and the solution (or last iterate) on exit; p_next gets p^{k+1}. With
  // opt.reuse_jacobian the factorisation of an earlier iteration or step may serve as the
  // Jacobian (a simplified Newton step), as long as the iteration contracts fast.
  SolveInfo solve(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                  const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                  Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next);

  // Drops the kept factorisation (reuse_jacobian), so that the next solve depends on its
  // arguments only.
  void forget_factorization() { factor_valid_ = false; }

  DelWorkspace del;          // Algorithm 1 at the current iterate (also for direct callers)
  NewtonWorkspace newton;    // for direct callers of newton_direction

 private:
  DelWorkspace del_trial_;   // Algorithm 1 at the trial point; swapped with del on acceptance
  DelWorkspace del_factor_;  // the kinematics the kept factorisation was computed at
  NewtonWorkspace factor_;   // the kept factorisation (newton_factor)
  bool factor_valid_ = false;
  MatX r_, r_trial_, dq_, dbar_, q_trial_;
  VecX p_trial_;
};

}  // namespace hovi
