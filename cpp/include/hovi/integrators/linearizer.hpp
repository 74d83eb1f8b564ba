// The linearisation of one converged step (q^k, p^k, u^k) -> (q^{k+1}, p^{k+1}) by the implicit
// function theorem on the DEL equations: with z = q^{k,1..s} and R(z; q^k, p^k, u) = 0,
//   dz/dx = -(dR/dz)^{-1} dR/dx,   q^{k+1} = z_s,   dp^{k+1}/dx = dP/dx + dP/dz dz/dx,
// one LU factorisation of dR/dz (sn x sn) serving every right-hand side.
//   A = d(q^{k+1}, p^{k+1}) / d(q^k, p^k)          (2n x 2n)
//   B = d(q^{k+1}, p^{k+1}) / d(u^{k,0..s})        (2n x (s+1) m), column block a = u^{k,a}
#pragma once
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"

namespace hovi {

class Linearizer {
 public:
  Linearizer(const Model& model, const Quadrature& quad, double dt);

  // The DEL Jacobian (see del_jacobian.hpp for the layout); Ju unless null.
  void del_jacobian(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX& Jq, MatX* Ju);
  // A and/or B (null: not computed, and no work done for it) at converged control points qc.
  // Returns false if dR/dz is singular.
  bool step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX* A, MatX* B);

 private:
  const Model& model_;
  const Quadrature& quad_;
  double dt_;
  DelJacobianWorkspace ws_;
  MatX Jq_, Ju_, rhs_, sol_;
};

}  // namespace hovi
