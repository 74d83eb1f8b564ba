#include "hovi/control/state_map.hpp"

#include <Eigen/Cholesky>

#include "hovi/algorithms/kinetic_hessians.hpp"
#include "hovi/algorithms/mass_matrix.hpp"

namespace hovi {

void velocity_state_map(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                        const Eigen::Ref<const VecX>& p, MatX& T) {
  const int n = model.n();
  const MatX M = mass_matrix(model, data, q);
  const Eigen::LLT<MatX> llt(M);
  const VecX qdot = llt.solve(p);
  kinetic_hessians(model, data, q, qdot);  // Kvv = M (armature included), Kvq = dp/dq at fixed q̇
  const Eigen::LLT<MatX> lv(data.Kvv);
  T.setZero(2 * n, 2 * n);
  T.topLeftCorner(n, n).setIdentity();
  T.bottomLeftCorner(n, n) = -lv.solve(data.Kvq);
  T.bottomRightCorner(n, n) = lv.solve(MatX::Identity(n, n));
}

}  // namespace hovi
