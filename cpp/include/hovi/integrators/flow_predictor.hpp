// The flow predictor of a rollout step (SolverOptions::predictor): the control points
// q^{k,a} ≈ q(t_k + c^a dt) of the continuous dynamics M(q) q̈ = Q - C q̇ - g from q^k and
// q̇^k = M(q^k)^{-1} p^k, by classical Runge-Kutta steps, O(n) each by the articulated-body
// algorithm: for s <= 2 one per interval between consecutive Lobatto points (4 s forward-dynamics
// passes); for s >= 3 m < s equal steps as long as the longest interval (rounded: m = 2 for s = 3,
// 3 for s = 4), with the points read off the quintic Hermite interpolant of (q, q̇, q̈) at their
// ends (4 m + 1 passes: 9 in place of 12, 13 in place of 16; as close to the converged points
// as one step per interval, bench/README.md). The joint forces (springs, dampers, actuators; the controls interpolated linearly between the
// control points) enter; force elements on bodies (BodyWrench) and constraints do not: it is a
// starting point for Newton, whose converged step does not depend on it.
//
// Why: at steps that resolve a chain's fast modes only barely, the polynomial extrapolated from
// the last two steps lands far from the solution and Newton needs many damped iterations and
// refactorisations; the flow starts much closer (figures: bench/README.md).
#pragma once
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/model/data.hpp"
#include "hovi/quadrature/lobatto.hpp"

namespace hovi {

class FlowPredictor {
 public:
  explicit FlowPredictor(const Model& model);
  // Columns 1..s of qc from column 0 (q^k), p^k and the controls u (m x (s+1)). Returns false,
  // leaving qc's columns 1..s unspecified, if the dynamics is singular or not finite there.
  bool predict(const Model& model, const Quadrature& quad, double dt, Data& data, const Eigen::Ref<const VecX>& p,
               const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc);
  // The number of Runge-Kutta steps over dt: s (one per interval), or fewer equal ones as long as
  // the longest interval, rounded (s = 3: 2, s = 4: 3).
  static int substeps(const Quadrature& quad);

 private:
  // q̈ at (q, q̇) with the joint forces at controls u_t into dv.
  void acceleration(const Model& model, Data& data, const VecX& q, const VecX& v, const VecX& u_t, VecX& dv);
  // The controls at time x dt (x in [0, 1]), linear between the control points, into u_t.
  void control_at(const Quadrature& quad, const Eigen::Ref<const MatX>& u, double x, VecX& u_t) const;
  // One classical Runge-Kutta step of length h of (q_, v_), q̈ at its start a0 given.
  void rk4(const Model& model, Data& data, double h, const VecX& a0, const VecX& u_mid, const VecX& u_end);
  VecX q_, v_, qs_, vs_, q0_, v0_, a0_, a1_, tau_, u0_, um_, u1_;
  VecX kq_[4], kv_[4];
};

// The predictor of each step of a rollout (from its third step on: the history needs two) under
// SolverOptions::predictor. Auto (for s >= 3; the history for s = 1, 2) starts with the history
// and takes the flow once a step from the history needed more than kEnough Newton iterations
// (kEnoughDense on the dense path), trying the history again after kProbeFirst steps (twice as
// many after each probe that needed more, up to kProbeMax) and keeping it when that step needs no
// more. At accuracy-relevant steps the history is as good and cheaper, hence the thresholds; for
// s = 1, 2 the flow does not help (their control points lie too far from the continuous flow).
// A second factorisation is no signal: near round-off the simplified Newton refactors on steps of
// three iterations. (The measurements behind these choices: bench/README.md.)
class PredictorChoice {
 public:
  static constexpr int kEnough = 4, kEnoughDense = 6, kProbeFirst = 16, kProbeMax = 1024;
  // dense: the solver factors by the dense path (small n), where an iteration is cheap against
  // the flow's forward dynamics, so the history may take kEnoughDense iterations.
  PredictorChoice(Predictor mode, int s, bool dense)
      : mode_(mode == Predictor::Auto && s < 3 ? Predictor::History : mode), enough_(dense ? kEnoughDense : kEnough) {}
  bool flow();                              // the next step's predictor: true for the flow
  void observe(bool flow, int iterations);  // what that step needed
 private:
  Predictor mode_;
  int enough_;
  bool flowing_ = false;
  int since_probe_ = 0, probe_every_ = kProbeFirst;
};

}  // namespace hovi
