// Box-FDDP (Mastalli et al. 2020, "Crocoddyl", feasibility-driven DDP; control limits by a box QP
// per stage, Tassa et al. 2014) on a ShootingProblem: the dynamics are the VI step and its exact
// Jacobians A^k, B^k; the second-order terms of the dynamics are dropped, as in FDDP.
//
// One loop with three hooks, as Crocoddyl's solvers: compute_direction (the stage derivatives, then
// the backward Riccati pass with the gaps f^k = f(x^k, u^k) - x^{k+1}), try_step (the nonlinear
// rollout that closes a fraction α of the gaps), stopping_criteria (feasible, and the projected
// control gradient sum_k |Q_u^k|^2 below tol, or the expected decrease at round-off). Steps are accepted on FDDP's expected improvement.
#pragma once
#include <string>
#include <vector>

#include "hovi/control/shooting_problem.hpp"

namespace hovi {

struct FddpOptions {
  int max_iterations = 500;
  double tol = 1e-9;          // on sum_k |Q_u^k|^2 (projected onto the free controls)
  double reg_init = 1e-9, reg_min = 1e-9, reg_max = 1e9;
  double accept = 0.1;        // accept a step when the cost falls by accept x expected (feasible)
  double accept_negative = 2; // ... or rises by less than this x |expected| (with gaps)
  int threads = 1;            // for the stage derivatives
};

struct FddpIteration {
  double cost, stop, step, reg, gaps;
};

struct FddpResult {
  MatX xs;                      // (N+1) x 2n
  MatX us;                      // N x m
  MatX control_points;          // N x ((s+1) n), as Rollout
  MatX impulses;                // N x impulses(): through contact, each step's
  std::vector<MatX> K;          // N feedback gains (m x 2n): u = us^k + K^k (x - xs^k)
  double cost = 0, stop = 0, gaps = 0;
  int iterations = 0;
  bool converged = false, feasible = false;
  std::string status;           // converged, max_iterations, step_failed, regularisation_limit, rollout_failed
  std::vector<FddpIteration> trace;
  double seconds = 0;
};

class BoxFddp {
 public:
  // problem must outlive the solver.
  BoxFddp(const ShootingProblem& problem, FddpOptions options = {});
  // From xs_init ((N+1) x 2n; empty: the rollout of us_init from x0) and us_init (N x m, clamped to
  // the bounds). A rollout that fails leaves gaps (FDDP starts infeasible).
  FddpResult solve(const MatX& xs_init, const MatX& us_init);

  // The hooks (public for tests and for MPC, which calls solve repeatedly).
  bool compute_direction();            // false: the backward pass failed at reg_max
  double try_step(double alpha);       // the cost of the trial, or +inf if a step failed
  bool stopping_criteria() const;

 private:
  void start(const MatX& xs_init, const MatX& us_init);
  bool calc_derivatives();
  bool backward_pass();
  void accept_trial(double alpha);
  double expected_improvement(double alpha) const;

  const ShootingProblem& pb_;
  FddpOptions opt_;
  int N_, nx_, nu_;
  std::vector<VecX> xs_, us_, fs_, xs_try_, us_try_, xnext_, xnext_try_, zs_, zs_try_;  // zs: contact impulses
  std::vector<MatX> qc_, qc_try_;
  std::vector<StageDerivatives> d_;
  std::vector<VecX> Vx_, Qu_, k_;
  std::vector<MatX> Vxx_, K_;
  std::vector<MatX> Quu_;
  double cost_ = 0, cost_try_ = 0, reg_ = 1e-9, stop_ = 0, dg_ = 0, dq_ = 0;
  bool feasible_ = false;
};

}  // namespace hovi
