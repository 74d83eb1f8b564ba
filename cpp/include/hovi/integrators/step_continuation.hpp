// Globalisation of one step of the (unconstrained) DEL equations by continuation in the step
// length. The momentum p^k = -D_1 L_d - F_d^{k,0} of eq. (DEL_general1) is given and does not
// depend on the step length h, so the DEL equations of one step form a one-parameter family
//   r(q^{k,1..s}; h) = 0,  h in (0, dt],
// whose solution near h = 0 is unique, q^{k,a}(h) = q^k + c^a h q̇^k + O(h^2) with
// q̇^k = M(q^k)^{-1} p^k (the physical branch). The continuation follows that branch from small h
// to dt with a tangent predictor and an undamped Newton corrector, and accepts a corrector only
// if it stays on the branch (see step_continuation.cpp). A fold of the branch (a turning point in
// h, where the DEL Jacobian becomes singular) before dt means that no solution at dt is
// continuously connected to q^k: the continuation then stops with the explicit status
// SolveStatus::ContinuationStalled instead of returning a root of another branch.
//
// For the 32-link pendulum of the paper's Fig. 2 (q, q̇ uniform in ±π/2), the trapezoidal
// branch has a fold below dt = 0.06 for most states: the step does not exist there, whatever the
// solver, and plain Newton's "successes" at such states are roots of other branches.
#pragma once
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

struct ContinuationOptions {
  double first_increment = 1.0;     // first h increment, relative to dt (1: try the whole step first)
  double min_increment = 1e-6;      // relative to dt: a smaller increment means the branch ends (fold)
  double max_contraction = 0.5;     // corrector: ||δq_{j+1}||_inf <= this ||δq_j||_inf (Deuflhard)
  int max_corrector_iterations = 8; // Newton iterations per corrector
  double max_displacement = 0.25;   // corrector: ||q - q_pred||_inf <= this ||q_pred - q_prev||_inf
  double max_tangent_mismatch = 0.25;  // ||q - q_prev - d (t_prev + t)/2||_inf <= this ||q - q_prev||_inf
  int max_iterations = 500;         // Newton iterations over the whole continuation (then MaxIterations)
};

// What a continuation did (for diagnostics; optional).
struct ContinuationReport {
  double h_reached = 0;  // the largest h with a solution on the branch (dt on success)
  int steps = 0;         // accepted continuation steps
  int rejected = 0;      // rejected corrector attempts (each halves the increment)
  int fold_parity_rejections = 0;  // of them, those that landed on a root with the wrong sign of det J
};

// Workspace of step_continuation (sized once per model and quadrature; reuse it across calls).
struct ContinuationWorkspace {
  ContinuationWorkspace(const Model& model, const Quadrature& quad);
  DelWorkspace del_h;  // residuals at h ± ε for the h-derivative of r
  Data data;           // q̇^k = M^{-1} p^k
  MatX q_prev, q_pred, tangent, r, r_plus, r_minus, dq;
  VecX p_scratch;
};

// Solves the DEL equations r(q^{k,0..s}) = 0 of one step of length dt of a model without
// constraints (throws InputError otherwise) by continuation in the step length, with the Newton
// direction of `solver` (Algorithms 1, A.1, A.2). Arguments as NewtonSolver::solve: qc (n x (s+1)) column 0 is q^k on entry (the other
// columns are ignored: the path starts from q^k + c^a h q̇^k); on exit qc holds the solution (or
// the last point of the branch), p_next p^{k+1}. The stopping rule at dt is NewtonSolver::solve's
// with `opt`, which polishes the last corrector iterate. Status: Converged, ContinuationStalled
// (the branch has no solution at dt: a fold, see above), MaxIterations (budget spent), NonFinite.
// SolveInfo counts every Newton direction, factorisation and residual evaluation.
SolveInfo step_continuation(NewtonSolver& solver, ContinuationWorkspace& ws, const Model& model,
                            const Quadrature& quad, const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                            const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                            const ContinuationOptions& copt = {}, ContinuationReport* report = nullptr);

// The same with a workspace of its own (allocates).
SolveInfo step_continuation(NewtonSolver& solver, const Model& model, const Quadrature& quad,
                            const SolverOptions& opt, const Eigen::Ref<const VecX>& p,
                            const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                            const ContinuationOptions& copt = {}, ContinuationReport* report = nullptr);

// sign det of the DEL Jacobian ∂r/∂q^{k,1..s} from the pivot blocks Λ_i of the last
// newton_factor (Algorithm A.2 is a block elimination over the tree: det J = Π_i det Λ_i).
int jacobian_determinant_sign(const NewtonWorkspace& factor);

// The sign of det J on the physical branch as h -> 0: J -> (1/h) K ⊗ M(q^k) with
// K(a, c) = Σ_α w^α b^{αa} b^{αc} (a = 0..s-1, c = 1..s; the kinetic term of D^2 L_d), M SPD.
int small_step_determinant_sign(const Quadrature& quad, int n);

}  // namespace hovi
