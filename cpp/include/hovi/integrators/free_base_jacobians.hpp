// The linearisation of one converged step of a model with a free base (algorithms/free_base.hpp), the
// free-base part of Linearizer (linearizer.hpp), in tangent coordinates: the state
// δx = (q ⊖ q_ref, p - p_ref), ⊖ FreeBase::difference (Pinocchio's) and p the public momentum, so
//   A = d(δq^{k+1}, δp^{k+1}) / d(δq^k, δp^k) (2n x 2n),  B = d(δq^{k+1}, δp^{k+1}) / du^{k,0..s}.
// The step is solved in the chart about its start's attitude C (θ^{k,0} = 0). A tangent perturbation
// (δv, δω, δr) of q^k moves the base's position by C δv, the chart's centre to C exp(δω) (every point's
// chart coordinates held) and the joints by δr; y = q^{k,1..s} follows by the implicit function theorem
// on R(y; q^k, p^k, u, C) = 0 as in linearizer.hpp, and the outputs through the public maps at q^{k+1}
// (docs/how-it-works.md, "The free base"). Exact but for R's derivative by the centre's turn (central
// differences of the explicit residual, six evaluations) and the chart's A(θ) second derivative in the
// centre term's (central differences of its closed form): errors about 1e-10 of their scale.
#pragma once
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/free_base.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

class FreeBaseJacobians {
 public:
  // model and quad must outlive it; the model has a free base and no constraints.
  FreeBaseJacobians(const Model& model, const Quadrature& quad, double dt);

  // A and/or B (null: not computed) at a converged step's control points qc (n x (s+1), the chart
  // about `centre`, the attitude of q^k) with controls u (m x (s+1)). False if dR/dy is singular.
  bool step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, const Mat3& centre, MatX* A,
                      MatX* B) const;

 private:
  struct Workspace {
    Workspace(const Model& model, const Quadrature& quad) : jac(model, quad), res(model, quad) {}
    DelJacobianWorkspace jac;
    DelWorkspace res;
    MatX Jq, Ju, r, rp, rm, dR_dw, sol;
    VecX zero, pn, pp, pm;
  };
  // (r^{k,0..s-1}, p^{k+1}) at control points q with p^k = 0, the centre's placement already set.
  void residual(Workspace& w, const Eigen::Ref<const MatX>& q, const Eigen::Ref<const MatX>& u, MatX& r,
                VecX& p_next) const;

  const Model& model_;
  const Quadrature& quad_;
  double dt_;
  FreeBase base_;
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
