#include "hovi/algorithms/gravity_hessian.hpp"

#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

const MatX& gravity_hessian(const Model& model, Data& data, const Eigen::Ref<const VecX>& q) {
  forward_kinematics(model, data, q);
  return gravity_hessian(model, data);
}

const MatX& gravity_hessian(const Model& model, Data& data) {
  const int n = model.n();
  const Mat3 G = hat(model.gravity);
  for (int i = 0; i < n; ++i) {
    data.sigma_m[i] = model.M[i].m;
    data.sigma_p[i] = model.M[i].m * data.g[i].p;
  }
  data.Vqq.setZero();
  for (int i = n - 1; i >= 0; --i) {
    const Vec3 sbar = data.Sbar[i].head<3>(), nbar = data.Sbar[i].tail<3>();
    const Vec3 sigmaA = G * (data.sigma_m[i] * nbar - data.sigma_p[i].cross(sbar));  // σ^A = ĝ (σ_m n̄ - σ̂_p s̄)
    for (int j = i; j >= 0; j = model.parent[j]) data.Vqq(i, j) = data.Vqq(j, i) = data.Sbar[j].head<3>().dot(sigmaA);
    const int p = model.parent[i];
    if (p >= 0) {
      data.sigma_m[p] += data.sigma_m[i];
      data.sigma_p[p] += data.sigma_p[i];
    }
  }
  return data.Vqq;
}

}  // namespace hovi
