// The Galerkin variational integrator of order 2s on s+1 Lobatto control points: one step
// (q^k, p^k, u^k) -> (q^{k+1}, p^{k+1}) and rollouts over many steps, entirely in C++.
//
// Controls: u^{k,a} is given at each control point (an m x (s+1) matrix per step). Samples of a
// smooth u(t) keep the order 2s; a control held constant over each step (zero-order hold) is
// integrated to order 2s for that piecewise-constant input, but is only a first-order
// approximation of a smooth u(t).
#pragma once
#include <memory>

#include "hovi/integrators/constrained_solver.hpp"
#include "hovi/integrators/flow_predictor.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/integrators/step_continuation.hpp"
#include "hovi/integrators/step_hook.hpp"
#include "hovi/model/data.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

struct Rollout {
  MatX q, p;                   // (N+1) x n: q^k, p^k
  MatX control_points;         // N x ((s+1) n): row k = vec(q^{k,0..s}) column-major (n per point)
  MatX multipliers;            // N x (s m_c): row k = vec(λ^{k,0..s-1}) column-major (constrained)
  MatX controls;               // N x ((s+1) m) as u: the controls a StepHook chose (empty without one)
  Eigen::VectorXi iterations;  // Newton iterations per step
  Eigen::VectorXi factorizations;  // of them, those with a fresh Jacobian factorisation
  VecX residual;               // final ||r||_inf per step
  std::vector<SolveStatus> status;
  int steps = 0;               // steps completed (less than N if a solve failed)
};

// The scratch memory of one call: every public call of GalerkinIntegrator leases one from a pool,
// so that one integrator can be used from several threads at once (each call gets its own).
struct IntegratorWorkspace {
  IntegratorWorkspace(const Model& model, const Quadrature& quad);
  NewtonSolver solver;
  std::unique_ptr<ConstrainedSolver> constrained;  // when the model has constraints
  std::unique_ptr<ContinuationWorkspace> continuation;  // made at the first step_continuation
  Data data;
  FlowPredictor flow;
};

// Thread safety: the model, quadrature, dt and options are fixed at construction (do not change
// `options` while calls are running); every other call may run concurrently on one object, and
// each call's result depends on its arguments only.
class GalerkinIntegrator {
 public:
  GalerkinIntegrator(Model model, int s, double dt, SolverOptions options = {});

  const Model& model() const { return model_; }
  const Quadrature& quadrature() const { return quad_; }
  double dt() const { return dt_; }
  SolverOptions options;

  // p = dL/dq̇ = M(q) q̇, O(n^2). Its inverse reads a velocity back from a momentum: q̇ = M(q)^{-1} p,
  // and for a constrained model the q̇ with Dh(q) q̇ = 0 nearest to M^{-1} p in the kinetic-energy
  // metric (tangent_velocity.hpp), O(n m + m^3). The total energy K + V at (q, q̇(q, p)).
  VecX momentum(const VecX& q, const VecX& qdot) const;
  VecX velocity(const VecX& q, const VecX& p) const;
  double energy(const VecX& q, const VecX& p) const;

  // Constraints (the model's, if any): their number of equations m_c and a consistent initial
  // state: q projected onto h(q) = 0 by Gauss-Newton (minimum-norm corrections), q̇ onto
  // Dh q̇ = 0 in the kinetic-energy metric. Throws InputError for redundant or inconsistent
  // constraints, a state too far off the manifold, or constraints that lock every degree of
  // freedom.
  int n_constraints() const { return model_.n_constraints(); }
  std::pair<VecX, VecX> project(const VecX& q, const VecX& qdot, double tol = 1e-12) const;
  VecX constraint_values(const VecX& q) const;
  MatX constraint_jacobian(const VecX& q) const;

  // One step. qc: n x (s+1), column 0 must be q^k; on entry columns 1..s are the initial guess,
  // on exit the solution. u: m x (s+1). Constrained models: lambda (m_c x s) holds the guess of
  // λ^{k,0..s-1} on entry and the solution on exit (kept on failure); null: guess 0, not returned.
  SolveInfo step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc,
                 Eigen::Ref<VecX> p_next, MatX* lambda = nullptr) const;

  // One step with fallbacks: Newton from the extrapolated previous polynomial (if `previous` is
  // given; in rollouts, from guess_from_history once two steps are known), then from the
  // velocity guess, then from q^{k,a} = q^k, and last (models without constraints) by
  // continuation in the step length (step_continuation.hpp), which either finds the step on the
  // branch continuously connected to q^k or ends with ContinuationStalled; stopping at the first
  // that converges. qc column 0 must hold q^k. Iterations add up over the attempts.
  SolveInfo robust_step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                        const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                        MatX* lambda = nullptr) const;
  // The same, first from the rollouts' predictor of the last two steps' control points (either may
  // be empty: before_previous empty extrapolates `previous` alone). Models without constraints.
  SolveInfo robust_step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                        const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                        Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next) const;

  // Initial guesses for columns 1..s of qc (column 0 = q^k already set): from a velocity
  // estimate, q^k + c^a dt q̇; or by extrapolating the previous step's polynomial.
  void guess_from_velocity(const VecX& qdot, Eigen::Ref<MatX> qc) const;
  void guess_from_previous(const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc) const;
  // The predictor of rollouts: the least-squares polynomial of degree max(2, 2s-1) (at most 7)
  // through the 2s+1 control points of the last two steps, extrapolated to this step's points
  // and shifted through q^k. Measured on the 12-link pendulum (bench/README.md): 10 to 100
  // times closer to the solution than extrapolating the previous step alone (s = 2..4).
  void guess_from_history(const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                          Eigen::Ref<MatX> qc) const;

  // N steps from (q0, p0). u: N x ((s+1) m), row k = vec(u^{k,0..s}) column-major; may have 0
  // columns when the model has no controls. previous: control points of the step before
  // (n x (s+1)) for the first guess, or empty to start from M^{-1} p0; lambda0: the first
  // multiplier guess (m_c x s; empty: zero). Stops at the first failed solve. hook: asked for each
  // step's controls (and impulses) instead of u (then u may be empty), e.g. a feedback policy.
  Rollout rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, const MatX& previous = MatX(),
                  const MatX& lambda0 = MatX(), StepHook* hook = nullptr) const;

  // What every rollout (this one's, the contact simulator's) does alike: start_rollout checks q0,
  // p0, N and the controls u (N x ((s+1) m), InputError naming what does not fit) and sizes `out`
  // for N steps with row 0 = (q0, p0); step_controls unpacks step k's u^{k,0..s} (m x (s+1));
  // record_step stores step k's solve and, if it converged, q^{k+1}, p^{k+1} and its control points.
  // With a hook, u is not read (the hook gives each step's controls) and `controls` records them.
  void start_rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, Rollout& out, bool hooked = false) const;
  void step_controls(const MatX& u, int k, MatX& uk) const;
  // A hooked rollout's step k: the hook's controls into uk (and out.controls) and its momentum into p (and out.p).
  void hooked_controls(StepHook& hook, int k, Rollout& out, VecX& p, MatX& uk) const;
  void record_step(Rollout& out, int k, const SolveInfo& info, const Eigen::Ref<const MatX>& qc,
                   const Eigen::Ref<const VecX>& p_next) const;

  // The DEL residual and Newton direction at given control points (for tests and tools).
  void residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                Eigen::Ref<MatX> r, Eigen::Ref<VecX> p_next) const;
  bool direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                 Eigen::Ref<MatX> dq) const;
  // The constrained residual (r: n x s with the constraint forces, H: m_c x s) and direction
  // (ConstrainedSolver); the direction returns false if the KKT system is singular. Throws
  // InputError without constraints.
  void constrained_residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                            const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, MatX& r, MatX& H,
                            Eigen::Ref<VecX> p_next) const;
  bool constrained_direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                             const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, MatX& dz,
                             MatX& dlambda) const;

 private:
  SolveInfo step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                 Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, MatX& lambda) const;
  // flow: the first guess from the flow predictor instead of the history (rollouts, options.predictor)
  SolveInfo robust_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                        const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                        Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, MatX& lambda, bool flow = false) const;
  MatX lambda_guess(const MatX* lambda) const;

  Model model_;
  Quadrature quad_;
  double dt_;
  MatX extrapolate_;   // E(b, a) - E(b, 0), E(b, a) = l_b(1 + c^a), a = 1..s: for guess_from_previous
  MatX extrapolate2_;  // (2s+1) x s, likewise for guess_from_history
  mutable WorkspacePool<IntegratorWorkspace> pool_;
};

}  // namespace hovi
