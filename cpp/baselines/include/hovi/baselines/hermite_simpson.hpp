// Baseline for the paper's Sec. 5.3 / Fig. 4: Hermite-Simpson (HS) direct collocation used as an
// implicit simulator of the second-order system x = (q, v), ẋ = f(x, u) = (v, FD(q, v, tau)).
// One step x_k -> x_{k+1} of length h solves the HS collocation conditions
//   x_m     = (x_k + x_{k+1})/2 + h/8 (f_k - f_{k+1}),
//   x_{k+1} = x_k + h/6 (f_k + 4 f_m + f_{k+1}),
// i.e. the 3-stage Lobatto IIIA method. Sec. 5.3 calls it third order; its node values converge
// with order 4 for smooth problems (observed: 3.98-4.00 in test_hermite_simpson.cpp).
//
// Formulation: the IMPLICIT one of the paper's footnote (and of Posa 2016, Hereid 2018): the joint
// accelerations a_{k+1} and a_m are unknowns, f = (v, a), and the dynamics enter as the
// inverse-dynamics defects ID(q, v, a) - Q(q, v, u) = 0 at t_{k+1} and at the midpoint. The
// collocation conditions are then LINEAR in (q, v, a); they are eliminated exactly,
//   v_{k+1} = v_k + h/6 (a_k + 4 a_m + a_{k+1}),   q_{k+1} = q_k + h/2 (v_k + v_{k+1}) + h²/12 (a_k - a_{k+1}),
//   q_m = (q_k + q_{k+1})/2 + h/8 (v_k - v_{k+1}),   v_m = (v_k + v_{k+1})/2 + h/8 (a_k - a_{k+1}),
// which leaves 2n unknowns z = (a_{k+1}, a_m) and 2n residuals
//   r = (h/6 [ID - Q](q_{k+1}, v_{k+1}, a_{k+1}),  4h/6 [ID - Q](q_m, v_m, a_m)).
// Newton on this reduced system takes the same steps as Newton on the full implicit system
// ((8N+4)n variables in the paper's Table 1) started on its linear constraints. Why this one: the
// residual costs two O(n) RNEA passes and no mass-matrix inverse, and its Jacobian needs
// ∂ID/∂q, ∂ID/∂v and M, with no derivative of M(q)^{-1} as the compressed (unknowns x_{k+1},
// f through the ABA) form would need; the linear system has the compressed form's size 2n.
// a_k = FD(q_k, v_k, tau_k) comes from hovi's O(n) articulated-body forward_dynamics.
//
// The residual is weighted by the Simpson weights h/6, 4h/6 so that it is an impulse, like
// the DEL residual of hovi's NewtonSolver, and the iteration is newton_iterate with its stopping
// rule (newton_driver.hpp): ||r||_inf <= tol (1 + ||p_k||_inf), p_k = M(q_k) v_k, or the
// correction δz at round-off of z.
//
// Jacobian: ANALYTIC by default, O(n^2): the derivatives of recursive Newton-Euler in spatial
// coordinates (Carpentier & Mansard 2018, re-derived in hovi's world-frame conventions; see
// algorithms/rnea_derivatives.hpp), plus M(q) from the same composite inertias. FiniteDifference
// instead differentiates the reduced residual by central differences (8n RNEA passes, O(n^2)).
// The 2n x 2n Newton system is solved densely by partial-pivoting LU, O(n^3); it is reported
// singular when min|U_ii| <= 1e-14 max|U_ii|.
//
// Forces: gravity, the joint springs/dampers/actuation of model.joint_forces,
//   Q = preload - k q - c v + B u. Body wrench elements and holonomic constraints are not
// supported (ModelError).
#pragma once
#include <vector>

#include "hovi/algorithms/rnea_derivatives.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

enum class HermiteSimpsonJacobian { Analytic, FiniteDifference };

struct HermiteSimpsonOptions {
  double tol = 1e-10;       // ||r||_inf <= tol (1 + ||M(q_k) v_k||_inf)
  int max_iterations = 30;  // Newton directions per attempt
  int max_backtracks = 12;  // halvings of the step before the line search gives up
  bool line_search = true;  // Armijo backtracking on ||r||_2; false: full Newton steps
  HermiteSimpsonJacobian jacobian = HermiteSimpsonJacobian::Analytic;
  // Simplified Newton within a step, as the VI's solver: the Jacobian and its LU from the first
  // iteration are kept while each correction is at most 0.1 of the previous one.
  bool reuse_jacobian = true;
};

struct HermiteSimpsonRollout {
  MatX q, v;                   // (N+1) x n: q_k, v_k
  MatX a;                      // (N+1) x n: a_k = FD(q_k, v_k, tau_k); row N is a_N from the last
                               // solve; rows not reached (and row 0 when N = 0) are NaN
  Eigen::VectorXi iterations;  // Newton iterations per step (summed over the fallback attempts), 0 if not reached
  VecX residual;               // final ||r||_inf per step, NaN if not reached
  std::vector<SolveStatus> status;
  int steps = 0;               // steps completed (less than N if a solve failed)
};

class HermiteSimpson {
 public:
  // Throws InputError unless dt > 0 finite, tol > 0, max_iterations >= 1, max_backtracks >= 0;
  // ModelError if the model has no joints, body wrench elements or constraints.
  HermiteSimpson(const Model& model, double dt, HermiteSimpsonOptions options = {});

  const Model& model() const { return model_; }
  double dt() const { return dt_; }
  HermiteSimpsonOptions options;

  // One step from x_k = (q, v). u: m x 3, the controls at t_k, t_k + h/2, t_k + h (ignored, may
  // be empty, when the model has no controls). guess: optional n x 2 initial (a_{k+1}, a_m);
  // empty means a_{k+1} = a_m = a_k. On success q_next, v_next hold x_{k+1}; otherwise the last
  // iterate. The node and midpoint values of the last solve: a_next(), q_mid(), ...
  SolveInfo step(const VecX& q, const VecX& v, const MatX& u, VecX& q_next, VecX& v_next,
                 const MatX& guess = MatX());

  // N steps from (q0, v0). u: N x (3 m), row k = (u^{k,0}, u^{k,1/2}, u^{k,1}) (m per point), 0
  // columns when the model has no controls. The guess of step k > 0 extrapolates the quadratic
  // a(t) of step k-1; on failure the step is retried from a_{k+1} = a_m = a_k. Stops at the first
  // failed step.
  HermiteSimpsonRollout rollout(const VecX& q0, const VecX& v0, int N, const MatX& u = MatX());

  // The collocation conditions in their original state form, with f evaluated by the ABA
  // (independent of the solver's RNEA): returns (x_{k+1} - x_k - h/6 (f_k + 4 f(x_m) + f_{k+1}))
  // with x_m from the first condition, 2n entries (q rows, then v rows).
  VecX collocation_residual(const VecX& q, const VecX& v, const VecX& q_next, const VecX& v_next,
                            const MatX& u = MatX());

  // The last step's node and midpoint values.
  const VecX& a_k() const { return a0_; }
  const VecX& a_next() const { return a1_; }
  const VecX& q_mid() const { return qm_; }
  const VecX& v_mid() const { return vm_; }
  const VecX& a_mid() const { return am_; }

 private:
  void set_controls(const MatX& u);                   // checks and stores u at the 3 points
  void states_from_accelerations(const VecX& z);      // q1, v1, qm, vm from z = (a1, am)
  void residual(const VecX& z, VecX& r);              // reduced residual, impulse units
  void jacobian(const VecX& z, VecX* r = nullptr);   // J_ = ∂r/∂z (and r, analytic only)
  VecX joint_force(int point, const VecX& q, const VecX& v) const;  // Q = preload - k q - c v + B u
  SolveInfo newton(VecX& z);

  Model model_;
  double dt_;
  Data data_;
  RneaDerivatives d1_, dm_;
  MatX J_, u3_;                       // Jacobian; controls at the 3 points (m x 3)
  VecX q0_, v0_, a0_, q1_, v1_, a1_, qm_, vm_, am_, r_, r_trial_, z_trial_, dz_;
  double residual_scale_ = 1;        // 1 + ||p_k||_inf, the scale of the residual test
  struct Step;                       // the Problem of newton_iterate (hermite_simpson.cpp)
};

}  // namespace hovi
