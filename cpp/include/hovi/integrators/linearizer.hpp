// The linearisation of one converged step (q^k, p^k, u^k) -> (q^{k+1}, p^{k+1}) by the implicit
// function theorem on the DEL equations: with y = q^{k,1..s} (and the multipliers λ^{k,0..s-1}
// of a constrained model) and R(y; q^k, p^k, u) = 0,
//   dy/dx = -(dR/dy)^{-1} dR/dx,   q^{k+1} = q^{k,s},   dp^{k+1}/dx = dP/dx + dP/dy dy/dx,
// one LU factorisation of dR/dy serving every right-hand side.
//   A = d(q^{k+1}, p^{k+1}) / d(q^k, p^k)          (2n x 2n)
//   B = d(q^{k+1}, p^{k+1}) / d(u^{k,0..s})        (2n x (s+1) m), column block a = u^{k,a}
// Constrained models: R adds the constraint rows h(q^{k,1..s}) (Dh) and the constraint forces
// w^a dt Dh(q^{k,a})^T λ^{k,a} (their λ·d²h terms come with the force elements of the
// augmented model, constraint.hpp).
// With contacts the step is the contact step (its impulses z among the unknowns), linearised with
// each contact's state held (smoothing = 0) or smoothed across contact switches (smoothing > 0):
// contact_jacobians.hpp.
// A free base: the step in tangent coordinates, from its start's attitude (free_base_jacobians.hpp).
#pragma once
#include <memory>

#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/integrators/contact_jacobians.hpp"
#include "hovi/integrators/free_base_jacobians.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"

namespace hovi {

// Thread safety: every call leases its own workspace, so one Linearizer serves several threads.
class Linearizer {
 public:
  // The linearisation of integ's steps (its model, quadrature, dt and contacts); integ must outlive it.
  explicit Linearizer(const GalerkinIntegrator& integ);
  const Model& model() const { return model_; }
  const Quadrature& quadrature() const { return quad_; }
  bool has_contacts() const { return contact_ != nullptr; }

  // The DEL Jacobian (see del_jacobian.hpp for the layout). For a constrained model with
  // multipliers lambda (m_c x s), the equations include the constraint forces (and so their
  // λ·d²h terms), Ju gains the columns of the multipliers (controls [u; λ] at each control
  // point, λ^{k,s} = 0), and Dh (m_c s x n (s+1)) gets h(q^{k,1..s})'s Jacobian.
  void del_jacobian(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX& Jq, MatX* Ju,
                    const Eigen::Ref<const MatX>& lambda = MatX(), MatX* Dh = nullptr) const;
  // A and/or B (null: not computed, and no work done for it) at converged control points qc with
  // the step's other unknowns w: the multipliers λ^{k,0..s-1} (m_c x s) of a constrained model, or
  // with contacts the impulses z (unknowns() x 1), linearised with smoothing (0: each contact's state
  // held). Returns false if dR/dy is singular. Yx, Yu (if given): the sensitivities of the step's
  // interior and last control points y = q^{k,1..s} (s n rows, point a-1 in rows (a-1) n ..),
  // dy/d(q^k, p^k) (s n x 2n) and dy/du (s n x (s+1) m): what a cost on the control points needs
  // (the FDDP of control/; through contact s = 1, y = q^{k+1}). A free base: `start` is the step's
  // public q^k (nq), whose attitude is the chart's centre; A and B act on tangent coordinates.
  bool step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX* A, MatX* B,
                      const Eigen::Ref<const MatX>& w = MatX(), MatX* Yx = nullptr, MatX* Yu = nullptr,
                      double smoothing = 0, const Eigen::Ref<const VecX>& start = VecX()) const;
  // step_jacobians along K converged steps: control points C (K x (s+1) n, row k = vec(q^{k,0..s})
  // column-major), controls U (K x (s+1) m, likewise) and the steps' other unknowns W (K x s m_c,
  // vec(λ^{k,0..s-1}), of a constrained model; K x unknowns() with contacts; else empty). A_k goes
  // to As[k] and B_k to Bs[k], row-major blocks of a (K, 2n, 2n) and a (K, 2n, (s+1) m) array (null:
  // not computed). Returns -1, or the first step whose dR/dy is singular (the blocks from it on are
  // left as they were). A free base: the steps' public starts q^k (K x nq).
  int trajectory_jacobians(const Eigen::Ref<const MatX>& C, const Eigen::Ref<const MatX>& U,
                           const Eigen::Ref<const MatX>& W, double* As, double* Bs, double smoothing = 0,
                           const Eigen::Ref<const MatX>& starts = MatX()) const;

 private:
  struct Workspace {
    Workspace(const Model& aug, const Model& model, const Quadrature& quad) : ws(aug, quad), data(model) {}
    DelJacobianWorkspace ws;
    Data data;
    MatX Jq, Ju, K, rhs, sol, uaug, Dh;
  };

  const Model& model_;
  const Quadrature& quad_;
  double dt_;
  int mc_, nz_;  // constraint equations; contact unknowns per step
  Model aug_;  // the model with its constraint forces (constraint.hpp); == model_ without constraints
  std::unique_ptr<ContactJacobians> contact_;  // with contacts
  std::unique_ptr<FreeBaseJacobians> free_;    // with a free base
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
