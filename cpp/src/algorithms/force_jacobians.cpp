#include "hovi/algorithms/force_jacobians.hpp"

#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

ForceJacobians::ForceJacobians(const Model& model)
    : Q(model.n()), Qq(model.n(), model.n()), Qv(model.n(), model.n()), Qu(model.n(), model.n_controls()) {}

void force_jacobians(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                     const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& u, ForceJacobians& out,
                     bool with_u) {
  const int m = model.n_controls();
  const JointForces& jf = model.joint_forces;
  out.Q.setZero();
  out.Qq.setZero();
  out.Qv.setZero();
  if (with_u) out.Qu.setZero();
  if (jf.has_springs()) {
    out.Q += jf.preload - jf.stiffness.cwiseProduct(q);
    out.Qq.diagonal() -= jf.stiffness;
  }
  if (jf.has_dampers()) {
    out.Q -= jf.damping.cwiseProduct(qdot);
    out.Qv.diagonal() -= jf.damping;
  }
  if (m > 0) {
    out.Q += jf.actuation * u;
    if (with_u) out.Qu += jf.actuation;
  }
  if (model.wrenches.empty()) return;
  forward_kinematics(model, data, q, qdot);
  std::vector<int> path;
  MatX Du(6, m);
  for (const auto& w : model.wrenches) {
    const int b = w->body();
    const Wrench F = w->value(data.g[b], data.v[b], u);
    Mat6 D1 = Mat6::Zero(), D2 = Mat6::Zero();
    w->add_derivatives(data.g[b], data.v[b], u, D1, D2);
    const Mat6 adDF = adD(F);
    path.clear();
    for (int j = b; j >= 0; j = model.parent[j]) path.push_back(j);  // b, par(b), ..., root
    for (int pj = 0; pj < static_cast<int>(path.size()); ++pj) {
      const int j = path[pj];
      out.Q[j] += data.Sbar[j].dot(F);
    }
    for (int pl = 0; pl < static_cast<int>(path.size()); ++pl) {
      const int l = path[pl];
      const int pa = model.parent[l];
      const Twist dv = ad(data.Sbar[l], pa >= 0 ? Twist(data.v[b] - data.v[pa]) : data.v[b]);
      const Wrench col_q = D1 * data.Sbar[l] + D2 * dv;
      const Wrench col_v = D2 * data.Sbar[l];
      const Wrench col_S = adDF * data.Sbar[l];
      for (int pj = 0; pj < static_cast<int>(path.size()); ++pj) {
        const int j = path[pj];
        // l ∈ anc(j) ∪ {j} iff l is at or above j on the path
        out.Qq(j, l) += data.Sbar[j].dot(pl >= pj ? Wrench(col_q + col_S) : col_q);
        out.Qv(j, l) += data.Sbar[j].dot(col_v);
      }
    }
    if (with_u && w->max_control_index() >= 0) {
      Du.setZero();
      w->add_control_jacobian(data.g[b], data.v[b], u, Du);
      for (int j : path) out.Qu.row(j) += data.Sbar[j].transpose() * Du;
    }
  }
}

}  // namespace hovi
