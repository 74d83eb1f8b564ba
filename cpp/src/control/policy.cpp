#include "hovi/control/policy.hpp"

#include <algorithm>
#include <string>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

void Policy::check(const Model& model, int s) const {
  const int S = stages(), n = model.n(), nq = model.nq(), m = model.n_controls();
  if (S < 1) throw InputError("a policy needs at least one gain");
  if (x_ref.rows() != S || x_ref.cols() != nq + n)
    throw InputError("the policy's reference states must be (" + std::to_string(S) + ", nq + n = " +
                     std::to_string(nq + n) + ")");
  if (u_ref.rows() != S || u_ref.cols() != (s + 1) * m)
    throw InputError("the policy's reference controls must be (" + std::to_string(S) + ", (s+1) m = " +
                     std::to_string((s + 1) * m) + ")");
  for (int k = 0; k < S; ++k)
    if (K[k].rows() != m || K[k].cols() != 2 * n || !K[k].allFinite())
      throw InputError("the policy's gain " + std::to_string(k) + " must be finite and (m, 2n) = (" + std::to_string(m) +
                       ", " + std::to_string(2 * n) + ")");
  if (!x_ref.allFinite() || !u_ref.allFinite()) throw InputError("the policy's references hold NaN or infinity");
  if (lower.size() != m || upper.size() != m || lower.hasNaN() || upper.hasNaN() || (lower.array() > upper.array()).any())
    throw InputError("the policy's control limits must be m numbers with lower <= upper (no NaN)");
}

void Policy::control(int k, const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& p, MatX& uk,
                     const FreeBase* base) const {
  const int j = std::min(k, stages() - 1), n = int(p.size()), nq = int(q.size()), m = int(K[j].rows());
  const VecX q_ref = x_ref.row(j).head(nq).transpose();
  const VecX dq = base ? VecX(base->difference(q_ref, q)) : VecX(q - q_ref);  // q ⊖ q_ref
  const VecX du = -K[j].leftCols(n) * dq + K[j].rightCols(n) * (x_ref.row(j).tail(n).transpose() - p);  // -K (x - x_ref)
  for (int a = 0; a < uk.cols(); ++a)  // uk: m x (s+1), sized by the rollout
    uk.col(a) = (u_ref.row(j).segment(a * m, m).transpose() + du).cwiseMax(lower).cwiseMin(upper);
}

void check_pushes(const Model& model, const std::vector<Push>& pushes) {
  for (std::size_t i = 0; i < pushes.size(); ++i) {
    const Push& d = pushes[i];
    if (d.body < 0 || d.body >= model.n()) throw InputError("push " + std::to_string(i) + ": no body " + std::to_string(d.body));
    if (!d.point.allFinite() || !d.impulse.allFinite() || !d.angular.allFinite()) throw InputError("push " + std::to_string(i) + ": NaN or infinity");
    if (d.step < 0) throw InputError("push " + std::to_string(i) + ": a negative step");
  }
}

PushSchedule::PushSchedule(const Model& model, const std::vector<Push>& pushes)
    : model_(model), pushes_(pushes), data_(model), J_(3, model.n()) {
  if (model.rotation_chart >= 0) base_.emplace(model);
}

void PushSchedule::apply(int k, const VecX& q_state, VecX& p_state) {
  if (std::none_of(pushes_.begin(), pushes_.end(), [k](const Push& d) { return d.step == k; })) return;
  VecX q = q_state, p = VecX::Zero(model_.n());  // a free base: the chart about q's attitude, p's change in it
  Mat3 centre;
  if (base_) {
    q.resize(model_.n());
    base_->split(q_state, q, centre);
    data_.chart_placement = model_.chart_placement(centre);
  }
  forward_kinematics(model_, data_, q);
  for (const Push& d : pushes_) {
    if (d.step != k) continue;
    J_.setZero();
    Vec3 x;
    const Vec3 r = model_.point_in_com_frame(d.body, d.point);  // body frames sit at the COM (docs/paper.md C-3)
    body_point_jacobian(KinematicsView{model_, data_.g.data(), data_.Sbar.data(), 1}, d.body, r, x, J_);
    p.noalias() += J_.transpose() * d.impulse;
    for (int j = d.body; j >= 0; j = model_.parent[j]) p[j] += data_.Sbar[j].head<3>().dot(d.angular);  // ω_j . τ
  }
  if (base_) base_->momentum_to_public(q, centre, p);
  p_state += p;
}

}  // namespace hovi
