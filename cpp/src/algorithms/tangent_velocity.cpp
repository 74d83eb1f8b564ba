#include "hovi/algorithms/tangent_velocity.hpp"

#include <Eigen/LU>

#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/errors.hpp"

namespace hovi {

VecX tangent_velocity(const Model& model, Data& data, const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& v) {
  const int n = model.n(), m = model.n_constraints();
  if (m == 0) return v;
  forward_kinematics(model, data, q);
  MatX Dh(m, n);
  constraint_jacobian(model, KinematicsView{model, data.g.data(), data.Sbar.data(), 1}, Dh);
  MatX W(n, m);  // M^{-1} Dh^T, one articulated-body solve per constraint equation
  for (int c = 0; c < m; ++c) W.col(c) = mass_matrix_solve(model, data, q, Dh.row(c).transpose());
  const Eigen::PartialPivLU<MatX> lu(Dh * W);
  const MatX& S = lu.matrixLU();
  if (!(S.diagonal().cwiseAbs().minCoeff() > 1e-13 * S.cwiseAbs().maxCoeff()))
    throw InputError("the constraints are redundant or singular here (Dh M^-1 Dh^T is singular)");
  return v - W * lu.solve(Dh * v);
}

VecX velocity_from_momentum(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                            const Eigen::Ref<const VecX>& p) {
  const VecX v = mass_matrix_solve(model, data, q, p);
  return tangent_velocity(model, data, q, v);
}

}  // namespace hovi
