#include "hovi/algorithms/mass_matrix.hpp"

#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

const MatX& mass_matrix(const Model& model, Data& data, const Eigen::Ref<const VecX>& q) {
  forward_kinematics(model, data, q);
  const int n = model.n();
  data.Mq.setZero();  // entries of joints on different branches stay zero
  for (int i = 0; i < n; ++i) data.IA[i] = data.Mbar[i].matrix();
  for (int i = n - 1; i >= 0; --i)  // composite inertia of the subtree rooted at i
    if (model.parent[i] >= 0) data.IA[model.parent[i]] += data.IA[i];
  for (int i = n - 1; i >= 0; --i) {
    const Wrench F = data.IA[i] * data.Sbar[i];
    data.Mq(i, i) = data.Sbar[i].dot(F);
    for (int j = model.parent[i]; j >= 0; j = model.parent[j])
      data.Mq(i, j) = data.Mq(j, i) = data.Sbar[j].dot(F);
  }
  if (model.has_armature()) data.Mq.diagonal() += model.armature;  // M(q) + diag(a)
  return data.Mq;
}

}  // namespace hovi
