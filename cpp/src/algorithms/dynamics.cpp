#include "hovi/algorithms/dynamics.hpp"

#include <cmath>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

namespace {
// Bias wrench of a free body: -ad_v̄^T M̄ v̄ - F̄, so that M̄ a + bias is the net joint wrench.
Wrench body_bias(const Model& model, const Data& data, int i) {
  return -adT(data.v[i], data.Mbar[i] * data.v[i]) - gravity_wrench(model, data, i);
}
}  // namespace

namespace {
// The articulated-body algorithm after forward_kinematics(q, qdot): q̈ = M^{-1}(tau - bias),
// with the bias (velocity products and gravity) included or not.
const VecX& articulated_body(const Model& model, Data& data, const Eigen::Ref<const VecX>& qdot,
                             const Eigen::Ref<const VecX>& tau, bool with_bias) {
  const int n = model.n();
  const bool armature = model.has_armature();
  for (int i = 0; i < n; ++i) {
    data.c[i] = with_bias ? Twist(ad(data.v[i], data.Sbar[i]) * qdot[i]) : Twist::Zero();  // Ṡ̄_i q̇_i
    data.IA[i] = data.Mbar[i].matrix();
    data.pA[i] = with_bias ? body_bias(model, data, i) : Wrench::Zero();
  }
  for (int i = n - 1; i >= 0; --i) {
    data.U[i] = data.IA[i] * data.Sbar[i];
    data.D[i] = data.Sbar[i].dot(data.U[i]);
    if (armature) data.D[i] += model.armature[i];  // the joint's own inertia: M(q) + diag(a)
    data.u[i] = tau[i] - data.Sbar[i].dot(data.pA[i]);
    if (!(data.D[i] > 1e-14 * (1 + data.IA[i].norm())))
      throw ModelError("joint '" + model.spec[i].joint_name +
                       "' moves no mass or inertia: the mass matrix is singular; give the bodies it moves mass "
                       "or inertia, make it a fixed joint, or set an armature on it (Model.set_armature)");
    const int p = model.parent[i];
    if (p < 0) continue;
    const Mat6 Ia = data.IA[i] - data.U[i] * data.U[i].transpose() / data.D[i];
    data.IA[p] += Ia;
    data.pA[p] += data.pA[i] + Ia * data.c[i] + data.U[i] * (data.u[i] / data.D[i]);
  }
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    Twist a = data.c[i];
    if (p >= 0) a += data.a[p];
    data.qdd[i] = (data.u[i] - data.U[i].dot(a)) / data.D[i];
    data.a[i] = a + data.Sbar[i] * data.qdd[i];
  }
  return data.qdd;
}
}  // namespace

const VecX& forward_dynamics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                             const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& tau) {
  forward_kinematics(model, data, q, qdot);
  check_vector("tau", tau, model.n());
  return articulated_body(model, data, qdot, tau, true);
}

const VecX& mass_matrix_solve(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                              const Eigen::Ref<const VecX>& rhs) {
  forward_kinematics(model, data, q);
  check_vector("rhs", rhs, model.n());
  return articulated_body(model, data, rhs, rhs, false);
}

const VecX& inverse_dynamics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                             const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& qddot) {
  forward_kinematics(model, data, q, qdot);
  check_vector("qddot", qddot, model.n());
  const int n = model.n();
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    data.a[i] = ad(data.v[i], data.Sbar[i]) * qdot[i] + data.Sbar[i] * qddot[i];
    if (p >= 0) data.a[i] += data.a[p];
    data.pA[i] = data.Mbar[i] * data.a[i] + body_bias(model, data, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    data.tau[i] = data.Sbar[i].dot(data.pA[i]);
    if (model.parent[i] >= 0) data.pA[model.parent[i]] += data.pA[i];
  }
  if (model.has_armature()) data.tau += model.armature.cwiseProduct(qddot);  // diag(a) q̈
  return data.tau;
}

}  // namespace hovi
