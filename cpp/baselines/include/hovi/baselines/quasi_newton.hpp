// Baseline: the linear-time quasi-Newton method of Lee, Liu, Park, Srinivasa, "A Linear-Time
// Variational Integrator for Multibody Systems" (WAFR 2016, arXiv:1609.02898), their "recursive
// impulse-based quasi-Newton" (RIQN) method, Alg. 3, applied to hovi's trapezoidal DEL equations
// (s = 1). This is the O(n) method Fan et al.'s Fig. 2 compares against.
//
// What Lee et al. do (read in their reference code, github.com/jslee02/wafr2016,
// Skeleton::dm_integrate_RIQN_DRNEA / _SVI): with the DEL residual written as
//   f(q^{k+1}) = (momentum leaving the step) - (momentum entering) - (impulse)   (Lee Eqs. 3, 17;
//                                                          per body by DRNEA, Alg. 2, Eqs. 21-22)
// whose Jacobian is (1/dt) M + O(1), they replace the Jacobian by J_f ≈ (1/dt) M(q^k), the
// joint-space mass matrix at the *known* configuration q^k, held fixed during the iterations,
// and take the full step, with no line search:
//   q^{k+1}_{(l+1)} = q^{k+1}_{(l)} - dt M(q^k)^{-1} f(q^{k+1}_{(l)})                  (Lee Alg. 3)
// The step -dt M^{-1} f is the joint velocity change that the generalized impulse -dt f causes
// on the system at rest; it is computed in O(n) by the impulse form of the articulated-body
// algorithm (articulated inertias, bias impulses, velocity changes), never by forming M.
// (Equation and algorithm numbers as cited for arXiv:1609.02898 by DART's design note
// docs/design/simulation_variational_integrator.md; the update itself was checked in the code.)
//
// In hovi's sign convention r = p^k + D_1 L_d + F_d^{k,0} = -f (Algorithm 1), so the matrix the
// step inverts is J̃ = -(1/dt) M(q^k) ≈ ∂r/∂q^{k+1}, and the step is dq = -J̃^{-1} r = dt M(q^k)^{-1} r.
#pragma once
#include <vector>

#include "hovi/integrators/newton_solver.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

struct QuasiNewtonOptions {
  double tol = 1e-10;       // the Fig. 2 batch's residual test, ||r||_inf <= tol (1 + ||p^k||_inf), in the
                            // stopping rule of every Newton solver (newton_driver.hpp, step_tol kStepTol)
  int max_iterations = 100; // quasi-Newton steps (linear convergence needs more than Newton's 30)
};

class QuasiNewtonSolver {
 public:
  // Copies the model. The quadrature is the trapezoidal rule, Quadrature(1).
  QuasiNewtonSolver(const Model& model, double dt, QuasiNewtonOptions options = {});

  // Solves the trapezoidal DEL equations r(q^k, q^{k+1}) = 0 for q^{k+1}. qc (n x 2): column 0 is
  // q^k, column 1 the initial guess on entry and the solution (or last iterate) on exit; u is
  // m x 2 (m = model.n_controls(), may be 0 rows); p_next gets p^{k+1} at the last iterate.
  // Reports like NewtonSolver: iterations = quasi-Newton steps taken, residual = ||r||_inf at exit.
  // Status: Converged, MaxIterations, NonFinite (r, p^{k+1} or a step not finite), or
  // SingularJacobian (a joint that moves no mass: M(q^k) singular). Throws InputError on bad sizes.
  SolveInfo solve(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc,
                  Eigen::Ref<VecX> p_next);

  // The two halves of one step, public for tests. factor(q^k) computes the articulated-body
  // inertias of M(q^k) (the impulse-independent part of the ABI), O(n); returns false if M(q^k)
  // is singular. direction(r, dq) then gives dq = -J̃^{-1} r = dt M(q^k)^{-1} r, O(n).
  bool factor(const Eigen::Ref<const VecX>& qk);
  void direction(const Eigen::Ref<const VecX>& r, Eigen::Ref<VecX> dq);

  const Model& model() const { return model_; }
  const Quadrature& quadrature() const { return quad_; }
  double dt() const { return dt_; }
  QuasiNewtonOptions options;

 private:
  struct Step;                // the Problem of newton_iterate (quasi_newton.cpp)
  bool factor_articulated();  // from Sbar_, Mbar_ at q^k

  Model model_;
  Quadrature quad_;
  double dt_;
  DelWorkspace del_;
  Data data_;
  // Per body i, at q^k (Lee et al.'s ABI quantities, in hovi's spatial frame):
  std::vector<Twist> Sbar_;          // S̄_i(q^k), spatial joint twist
  std::vector<SpatialInertia> Mbar_; // M̄_i(q^k), spatial body inertia
  std::vector<Mat6> IA_;             // articulated-body inertia Î_i = M̄_i + Σ_c (Î_c - U_c U_c^T / D_c)
  std::vector<Wrench> U_;            // U_i = Î_i S̄_i
  VecX D_;                           // D_i = S̄_i^T Î_i S̄_i
  std::vector<Wrench> bias_;         // bias impulse β̂_i: what the subtree of i transmits to body i
  std::vector<Twist> dv_;            // spatial velocity change δv̄_i
  VecX uimp_;                        // u_i = Q_i - S̄_i^T β̂_i, joint impulse left for joint i
  MatX r_;                           // residual, n x 1
  VecX dq_;
};

}  // namespace hovi
