#include "hovi/algorithms/kinetic_hessians.hpp"

#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

void kinetic_hessians(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& qdot) {
  forward_kinematics(model, data, q, qdot);
  kinetic_hessians(model, data);
}

void kinetic_hessians(const Model& model, Data& data) {
  const int n = model.n();
  for (int i = 0; i < n; ++i) {
    data.Sdot[i] = ad(data.v[i], data.Sbar[i]);      // Ṡ̄_i = ad_{v̄_i} S̄_i
    data.mu[i] = data.Mbar[i] * data.v[i];           // own part of μ̄_i
    data.IA[i] = data.Mbar[i].matrix();              // own part of the composite inertia
  }
  data.Kvv.setZero();
  data.Kvq.setZero();
  data.Kqv.setZero();
  data.Kqq.setZero();
  for (int i = n - 1; i >= 0; --i) {  // children (higher indices) are complete when i is reached
    const Wrench MA = data.IA[i] * data.Sbar[i];
    const Wrench MB = data.IA[i] * data.Sdot[i] - adD(data.mu[i]) * data.Sbar[i];
    for (int j = i; j >= 0; j = model.parent[j]) {   // j in anc(i) ∪ {i}
      const double a = data.Sbar[j].dot(MA), b = data.Sdot[j].dot(MA);
      const double c = data.Sbar[j].dot(MB), d = data.Sdot[j].dot(MB);
      data.Kvv(i, j) = data.Kvv(j, i) = a;
      data.Kvq(i, j) = data.Kqv(j, i) = b;
      data.Kqv(i, j) = data.Kvq(j, i) = c;
      data.Kqq(i, j) = data.Kqq(j, i) = d;
    }
    const int p = model.parent[i];
    if (p >= 0) {
      data.mu[p] += data.mu[i];
      data.IA[p] += data.IA[i];
    }
  }
  if (model.has_armature()) data.Kvv.diagonal() += model.armature;  // 1/2 q̇^T diag(a) q̇: d2/dq̇2 only
}

}  // namespace hovi
