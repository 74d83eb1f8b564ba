// The variational integrator as the dynamics of a discrete optimal control problem (single
// shooting): state x^k = (q^k, p^k), controls u^k (m) held over step k, x^{k+1} = f(x^k, u^k) the VI
// step, and the cost of the trajectory optimiser's Problem on the control points of each step:
//   l^k = sum_a  |q^{k,a} - q_ref|^2_Wq + |q̇^{k,a} - q̇_ref|^2_Wv + |u^k - u_ref|^2_R,
//   q̇^{k,a} = (1/dt) sum_b b^{ab} q^{k,b}  (the transcription's samples, docs/paper.md C-1),
// with diagonal weights per sample (the quadrature weight w^a dt folded in), plus a terminal term on
// the last sample. Its derivatives come from the exact step Jacobians and the control points'
// sensitivities (Linearizer); the cost's Hessian is the Gauss-Newton one (the second derivatives of
// the control points dropped, as FDDP drops the dynamics').
//
// Through contact (an integrator with contacts, s = 1, no impact location): the step is the contact
// step and its Jacobians the Linearizer's, with the contact state held (smoothing = 0) or smoothed on the
// central path (smoothing > 0: gradients across contact switches); each step's impulses are kept with it.
#pragma once
#include <memory>
#include <vector>

#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/integrators/linearizer.hpp"

namespace hovi {

// One quadratic cost term on the samples. Running: rows = S (s+1), the samples of S stages (step k
// uses stage min(offset + k, S - 1)); terminal: one row, on the last sample of the horizon.
// Each array has `rows` rows (n or m columns); weights are diagonal and >= 0.
struct SampleCost {
  bool terminal = false;
  MatX Wq, q_ref, Wv, v_ref, R, u_ref;
};

// A cost computed outside for every step at once (hovi.trajopt.FDDP: a user's CallbackCost, one
// Python call per rollout and one per linearisation): its total value, and per step its gradient g
// and Gauss-Newton Hessian H in z = (vec(q^{k,0..s}), u^k) ((s+1) n + m), vec column-major as Rollout.
class StepCosts {
 public:
  virtual ~StepCosts() = default;
  virtual double value(const std::vector<MatX>& qc, const std::vector<VecX>& us) = 0;
  virtual void derivatives(const std::vector<MatX>& qc, const std::vector<VecX>& us, std::vector<VecX>& g,
                           std::vector<MatX>& H) = 0;
};

// The derivatives of a stage at a converged step.
struct StageDerivatives {
  MatX A, B;            // 2n x 2n, 2n x m
  VecX lx, lu;          // gradients of l^k
  MatX lxx, luu, lux;   // Gauss-Newton Hessian blocks
};

class ShootingProblem {
 public:
  // integ must outlive the problem; smoothing: the smoothing of the contact step's Jacobians (contacts
  // only). Throws InputError for sizes that do not fit, a model with constraints, negative or
  // non-finite weights, or contacts with s > 1, impact location or a bad smoothing.
  ShootingProblem(const GalerkinIntegrator& integ, int N, const VecX& x0, std::vector<SampleCost> costs,
                  const VecX& u_lower, const VecX& u_upper, double smoothing = 0);
  bool has_contacts() const { return integ_.has_contacts(); }
  int impulses() const { return integ_.contacts().unknowns(); }

  int N() const { return N_; }
  int nx() const { return 2 * n_; }
  int nu() const { return m_; }
  int s() const { return s_; }
  const VecX& x0() const { return x0_; }
  void set_x0(const VecX& x0);
  // The stage whose references step 0 uses (MPC: the time index of the horizon's start).
  int offset = 0;
  const VecX& u_lower() const { return lo_; }
  const VecX& u_upper() const { return hi_; }
  const GalerkinIntegrator& integrator() const { return integ_; }

  // Step k from x with u: x_next and the control points qc (n x (s+1)); qc's columns 1..s are the
  // first guess if `guessed`. Through contact, z (impulses()) holds the impulses' guess on entry (empty:
  // none active) and the step's on exit. False if the step does not converge.
  bool step(const VecX& x, const VecX& u, VecX& x_next, MatX& qc, bool guessed, VecX& z) const;
  // l^k at the step's control points.
  double stage_cost(int k, const MatX& qc, const VecX& u) const;
  // l^k's derivatives and the step's A, B at its converged control points; false if singular.
  // (Through contact: at the step's impulses z.) extra_g, extra_H: a StepCosts term of this step (or null).
  bool derivatives(int k, const MatX& qc, const VecX& u, const VecX& z, StageDerivatives& d,
                   const VecX* extra_g = nullptr, const MatX* extra_H = nullptr) const;
  // Costs computed outside (null: none); the caller keeps it alive.
  StepCosts* extra = nullptr;

 private:
  // The cost's gradient g (n x (s+1)) and Gauss-Newton Hessian H ((s+1) n square) in the control
  // points, and its u-parts, at stage k.
  void point_cost(int k, const MatX& qc, const VecX& u, double* value, MatX* g, MatX* H, VecX* gu, MatX* Huu) const;

  const GalerkinIntegrator& integ_;
  Linearizer lin_;
  double smoothing_ = 0;
  int N_, n_, m_, s_;
  VecX x0_, lo_, hi_;
  std::vector<SampleCost> costs_;
};

}  // namespace hovi
