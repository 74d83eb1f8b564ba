#include "hovi/algorithms/del_jacobian.hpp"

#include "hovi/algorithms/gravity_hessian.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/kinetic_hessians.hpp"

namespace hovi {

DelJacobianWorkspace::DelJacobianWorkspace(const Model& model, const Quadrature& quad)
    : data(model), forces(model), Kvv(quad.s + 1), Kvq(quad.s + 1), Kqv(quad.s + 1), Kqq(quad.s + 1),
      Vqq(quad.s + 1), qdot(model.n(), quad.s + 1) {}

void dlagrangian_hessian(const Model& model, const Quadrature& quad, DelJacobianWorkspace& ws,
                         const Eigen::Ref<const MatX>& qc, double dt, Eigen::Ref<MatX> D2Ld,
                         const DelWorkspace* kinematics) {
  const int n = model.n(), S1 = quad.s + 1;
  const VecX& w = quad.w;
  const MatX& b = quad.b;
  ws.qdot.noalias() = qc * b.transpose() / dt;
  const bool gravity = model.has_gravity();
  for (int a = 0; a < S1; ++a) {
    if (kinematics) kinematics->kinematics_at(a, ws.data);
    else forward_kinematics(model, ws.data, qc.col(a), ws.qdot.col(a));
    kinetic_hessians(model, ws.data);
    ws.Kvv[a] = ws.data.Kvv;
    ws.Kvq[a] = ws.data.Kvq;
    ws.Kqv[a] = ws.data.Kqv;
    ws.Kqq[a] = ws.data.Kqq;
    if (gravity) ws.Vqq[a] = gravity_hessian(model, ws.data);
  }
  for (int bb = 0; bb < S1; ++bb)
    for (int c = 0; c < S1; ++c) {
      auto blk = D2Ld.block(bb * n, c * n, n, n);
      blk.noalias() = (w[bb] * b(bb, c)) * ws.Kqv[bb] + (w[c] * b(c, bb)) * ws.Kvq[c];
      for (int a = 0; a < S1; ++a) {
        const double coef = w[a] / dt * b(a, bb) * b(a, c);
        if (coef != 0) blk.noalias() += coef * ws.Kvv[a];
      }
      if (bb == c) {
        blk.noalias() += (w[bb] * dt) * ws.Kqq[bb];
        if (gravity) blk.noalias() -= (w[bb] * dt) * ws.Vqq[bb];
      }
    }
}

void del_jacobian(const Model& model, const Quadrature& quad, DelJacobianWorkspace& ws,
                  const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> Jq,
                  MatX* Ju, const DelWorkspace* kinematics) {
  const int n = model.n(), m = model.n_controls(), S1 = quad.s + 1;
  dlagrangian_hessian(model, quad, ws, qc, dt, Jq, kinematics);
  const bool joint = model.joint_forces.any(), wrenches = !model.wrenches.empty();
  if (Ju) Ju->setZero(S1 * n, S1 * m);
  if (!joint && !wrenches) return;  // no non-conservative forces: nothing more to add
  for (int a = 0; a < S1; ++a) {
    const double wdt = quad.w[a] * dt;
    force_jacobians(model, ws.data, qc.col(a), ws.qdot.col(a), u.col(a), ws.forces, Ju != nullptr);
    Jq.block(a * n, a * n, n, n) += wdt * ws.forces.Qq;
    for (int c = 0; c < S1; ++c)
      if (quad.b(a, c) != 0) Jq.block(a * n, c * n, n, n) += (quad.w[a] * quad.b(a, c)) * ws.forces.Qv;
    if (Ju && m > 0) Ju->block(a * n, a * m, n, m) = wdt * ws.forces.Qu;
  }
}

}  // namespace hovi
