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
#include <Eigen/LU>
#include <functional>

#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/del_workspace.hpp"
#include "hovi/algorithms/free_base.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

// One step of a free base in tangent coordinates: its inputs (δv, δω, δr, δp) at q^k and outputs at
// q^{k+1}, for the step's chart about C (θ^{k,0} = 0) whose unknowns may be more than y (contact_jacobians.hpp).
class TangentStep {
 public:
  // qc: the control points; p0, pn: the chart momenta p^k and p^{k+1}.
  TangentStep(const FreeBase& base, const Mat3& centre, const Eigen::Ref<const MatX>& qc, const VecX& p0,
              const VecX& pn);
  // The input columns (rows x 2n) of a function with chart derivatives d_q0 by q^{k,0} (rows x n) and
  // d_turn by the centre's turn (rows x 3). with_p: its first n rows are r^{k,0} (d/dp^k = 1).
  MatX inputs(const MatX& d_q0, const MatX& d_turn, bool with_p) const;
  // The centre's turn δω of the inputs (3 x 2n).
  MatX turn() const;
  // out (2n x cols) = (δq^{k+1}, δp^{k+1}) from the chart's dq^{k+1}, dp^{k+1} and the centre's turn (3 x cols).
  void outputs(const MatX& dq_end, const MatX& dp_end, const MatX& turn, MatX& out) const;

 private:
  const FreeBase& base_;
  int n_, j_;
  Mat3 C_, Rs_, R1_, E_, M_;
  Eigen::PartialPivLU<Mat3> Et_;
  Vec3 p_lin0_, p_lin1_;
};

class FreeBaseJacobians {
 public:
  // model and quad must outlive it; the model has a free base and no constraints.
  FreeBaseJacobians(const Model& model, const Quadrature& quad, double dt);

  // A and/or B (null: not computed) at a converged step's control points qc (n x (s+1), the chart
  // about `centre`, the attitude of q^k) with controls u (m x (s+1)). False if dR/dy is singular.
  bool step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, const Mat3& centre, MatX* A,
                      MatX* B) const;
  // The DEL rows' and p^{k+1}'s derivative by the centre's turn ((s n + n) x 3), by central differences
  // of del_residual (p^k = 0) at the control points qc, plus the r^{k,0} force `knot` (n) adds at q^{k,0}
  // (contact impulses; null: none) about each turned centre; res: a workspace of this model's.
  void turn_derivative(DelWorkspace& res, const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                       const Mat3& centre, const std::function<VecX(const SE3&)>* knot, MatX& dR_dw) const;
  const FreeBase& base() const { return base_; }

 private:
  struct Workspace {
    Workspace(const Model& model, const Quadrature& quad) : jac(model, quad), res(model, quad) {}
    DelJacobianWorkspace jac;
    DelWorkspace res;
    MatX Jq, Ju, r, dR_dw, sol;
    VecX zero, pn;
  };

  const Model& model_;
  const Quadrature& quad_;
  double dt_;
  FreeBase base_;
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
