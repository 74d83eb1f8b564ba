#include "hovi/algorithms/energy.hpp"

#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

double kinetic_energy(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& qdot) {
  forward_kinematics(model, data, q, qdot);
  double K = 0;
  for (int i = 0; i < model.n(); ++i) K += 0.5 * data.v[i].dot(data.Mbar[i] * data.v[i]);
  if (model.has_armature()) K += 0.5 * model.armature.dot(qdot.cwiseProduct(qdot));  // 1/2 q̇^T diag(a) q̇
  return K;
}

double potential_energy(const Model& model, Data& data, const Eigen::Ref<const VecX>& q) {
  forward_kinematics(model, data, q);
  double V = 0;
  for (int i = 0; i < model.n(); ++i) V -= model.M[i].m * model.gravity.dot(data.g[i].p);
  const JointForces& jf = model.joint_forces;
  if (jf.has_springs())
    for (int i = 0; i < model.n(); ++i)
      if (jf.stiffness[i] != 0)  // 1/2 k (q - qref)^2
        V += 0.5 * jf.stiffness[i] * q[i] * q[i] - jf.preload[i] * q[i] + 0.5 * jf.preload[i] * jf.preload[i] / jf.stiffness[i];
  return V;
}

}  // namespace hovi
