// Newton's method on the DEL equations of one step, with the exact O(s^3 n) direction
// (Algorithms 1, A.1, A.2) and a backtracking line search. A damped step x + λ dx is accepted
// when it decreases the residual norm (Armijo) or passes Deuflhard's natural monotonicity test
// ||J(x)^{-1} r(x + λ dx)|| <= (1 - λ/4) ||dx||, which is affine invariant and escapes the false
// minima of ||r|| that stall a pure residual-norm search at large steps; the simplified
// correction costs one more O(s^2 n) recursive solve with the factorisation at x.
#pragma once
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/integrators/direction.hpp"
#include "hovi/integrators/newton_driver.hpp"

#include <memory>

namespace hovi {

enum class Reuse { Never, WithinStep };
// The first guess of a rollout step (galerkin_integrator.hpp): History extrapolates the last two
// steps' control points; Flow integrates the continuous dynamics over the step (flow_predictor.hpp,
// O(s) forward-dynamics passes); Auto chooses per step (flow_predictor.hpp's PredictorChoice).
enum class Predictor { Auto, History, Flow };

struct SolverOptions {
  // Converged when the estimated error of the iterate, the size of the next Newton correction
  // ||Δq||_inf, is at most step_tol (1 + ||q||_inf): by default at round-off, so that the
  // solver's error does not accumulate over long runs (no energy drift, no error floor under
  // the method's own error). If the corrections stop shrinking at a level below 1e-10 (1 + ||q||)
  // with a fresh Jacobian, or no fraction of such a correction reduces the residual, the
  // iterate is at the round-off floor of its residual: converged. (Why 1e-15: a looser default
  // lets the energy drift; bench/README.md.)
  double step_tol = kStepTol;
  // Optional residual test (0: off): also converged when ||r||_inf <= tol (1 + ||p^k||_inf).
  // A looser tol trades accuracy for fewer iterations.
  double tol = 0;
  int max_iterations = 30;
  int max_backtracks = 12;   // halvings of the step before the line search gives up
  bool line_search = true;   // false: always take the full Newton step
  double constraint_tol = 1e-12;  // constrained steps: also ||h(q^{k,1..s})||_inf <= this
  Direction direction = Direction::Auto;
  // Simplified Newton: keep the factorisation of the DEL Jacobian while the iteration contracts
  // fast (||Δq_k|| <= reuse_contraction ||Δq_{k-1}||) and full steps are accepted; refactor
  // otherwise. Never: a fresh factorisation every iteration (the paper's Newton); WithinStep:
  // factor at the predicted control points of each step and keep it for the step. (Keeping it
  // across steps as well was tried and dropped: many more iterations; bench/README.md.)
  // A reused factorisation costs an O(s^2 n) solve (recursive) or O(s^2 n^2) (dense) instead
  // of a new factorisation. The stopping test above makes the converged step independent of
  // which Jacobian was used, to round-off.
  Reuse reuse = Reuse::WithinStep;
  double reuse_contraction = 0.1;  // 0.25 failed on the 64-link pendulum at dt = 0.005 (s = 1); 0.1 as fast elsewhere
  Predictor predictor = Predictor::Auto;
};

// The stopping rule (newton_driver.hpp) and the iteration these options ask for; the residual
// test is relative to 1 + ||p^k||_inf.
StoppingRule stopping_rule(const SolverOptions& opt, const Eigen::Ref<const VecX>& p);
// A model with a free base: if its direction leaves out the chart term's derivative (exact = false: the
// recursive one, s = 1, the contact step's), the steadier contraction estimate and the last correction
// applied; else a correction more after a stop on the contraction's estimate (NewtonLoop).
NewtonLoop newton_loop(const SolverOptions& opt, const Model& model, bool exact);

class DenseDirection;

class NewtonSolver {
 public:
  NewtonSolver(const Model& model, const Quadrature& quad);
  ~NewtonSolver();
  // Solves r(q^{k,0..s}) = 0 for q^{k,1..s}. qc (n x (s+1)): column 0 is q^k, columns 1..s the
  // initial guess on entry and the solution (or last iterate) on exit; p_next gets p^{k+1}. With
  // opt.reuse the factorisation of an earlier iteration of this step may serve as the
  // Jacobian (a simplified Newton step), as long as the iteration contracts fast.
  SolveInfo solve(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                  const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                  Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next);

  // The Newton direction dq = -J^{-1} r at qc on the path opt.direction chooses, for the
  // residual r of the last del_residual call into `del` at the same qc. False if J is singular.
  bool direction(const Model& model, const Quadrature& quad, const SolverOptions& opt,
                 const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt,
                 const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq);

  // The free base's chart about its centre (Model::chart_placement) in every workspace of the solve.
  void set_chart_placement(const SE3& placement);

  DelWorkspace del;          // Algorithm 1 at the current iterate (also for direct callers)
  NewtonWorkspace newton;    // for direct callers of newton_direction

 private:
  struct Step;               // the Problem of newton_iterate (newton_solver.cpp)
  DelWorkspace del_trial_;   // Algorithm 1 at the trial point; swapped with del on acceptance
  // Factors the Jacobian at the current iterate (del, qc, its residual r) on the path chosen by opt.direction.
  bool factor(const Model& model, const Quadrature& quad, const SolverOptions& opt,
              const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt,
              const MatX& r);
  // dq = -J^{-1} r with the kept factorisation.
  void solve_direction(const Model& model, const Quadrature& quad, const Eigen::Ref<const MatX>& r,
                       Eigen::Ref<MatX> dq);

  DelWorkspace del_factor_;  // the kinematics the kept recursive factorisation was computed at
  NewtonWorkspace factor_;   // the kept recursive factorisation (newton_factor)
  std::unique_ptr<DenseDirection> dense_;  // made on first use of the dense path
  bool factor_valid_ = false, factor_dense_ = false;
  MatX r_, r_trial_, dq_, dbar_, q_trial_;
  VecX p_trial_;
};

}  // namespace hovi
