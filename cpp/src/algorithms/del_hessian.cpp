#include "hovi/algorithms/del_hessian.hpp"

#include <algorithm>

#include "hovi/util/central_differences.hpp"

namespace hovi {

DelHessianWorkspace::DelHessianWorkspace(const Model& model, const Quadrature& quad)
    : jac(model, quad), forces(model), on_path(model.n(), 0) {
  for (const auto& w : model.wrenches)   // a wrench on body b moves with the joints from b to the root
    for (int i = w->body(); i >= 0; i = model.parent[i]) on_path[i] = 1;
}

namespace {

// (Q_q^T nu, Q_v^T nu, Q_u^T nu) at z = (q, q̇, u): the gradient of nu . Q.
void force_gradient(const Model& model, DelHessianWorkspace& ws, const VecX& z, const Eigen::Ref<const VecX>& nu,
                    VecX& g) {
  const int n = model.n(), m = model.n_controls();
  force_jacobians(model, ws.jac.data, z.head(n), z.segment(n, n), z.tail(m), ws.forces, m > 0);
  g.resize(2 * n + m);
  g.head(n).noalias() = ws.forces.Qq.transpose() * nu;
  g.segment(n, n).noalias() = ws.forces.Qv.transpose() * nu;
  if (m > 0) g.tail(m).noalias() = ws.forces.Qu.transpose() * nu;
}

}  // namespace

void del_hessian(const Model& model, const Quadrature& quad, DelHessianWorkspace& ws, const Eigen::Ref<const MatX>& qc,
                 const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& nu, double dt, Eigen::Ref<MatX> Hqq,
                 Eigen::Ref<MatX> Huq, Eigen::Ref<MatX> Huu) {
  const int n = model.n(), m = model.n_controls(), S1 = quad.s + 1;
  Hqq.setZero();
  Huq.setZero();
  Huu.setZero();
  const double size = nu.cwiseAbs().maxCoeff();
  if (size == 0) return;
  // L_d: d/de D^2 L_d(q + e nu), central
  const double e = kCentralStep * std::max(1.0, qc.cwiseAbs().maxCoeff()) / size;
  ws.D2p.resize(S1 * n, S1 * n);
  ws.D2m.resize(S1 * n, S1 * n);
  ws.qp = qc + e * nu;
  dlagrangian_hessian(model, quad, ws.jac, ws.qp, dt, ws.D2p);
  ws.qp = qc - e * nu;
  dlagrangian_hessian(model, quad, ws.jac, ws.qp, dt, ws.D2m);
  Hqq = (ws.D2p - ws.D2m) / (2 * e);
  // forcing: body wrenches only (joint forces are linear); columns of (q, q̇, u) differenced only
  // where some wrench depends on them nonlinearly (q always; the others' rows come by symmetry)
  if (!model.wrenches.empty()) {
    const int Z = 2 * n + m;
    bool velocity = false, control = false;
    for (const auto& w : model.wrenches) {
      velocity = velocity || !w->velocity_free();
      control = control || !w->control_affine();
    }
    ws.z.resize(Z);
    ws.d.setOnes(Z);   // 1 where a column is differenced: no wrench moves with a joint off their paths
    for (int i = 0; i < n; ++i) ws.d[i] = ws.d[n + i] = ws.on_path[i];
    if (!velocity) ws.d.segment(n, n).setZero();
    if (!control) ws.d.tail(m).setZero();
    for (int a = 0; a < S1; ++a) {
      if (nu.col(a).cwiseAbs().maxCoeff() == 0) continue;
      ws.z.head(n) = qc.col(a);
      ws.z.segment(n, n).noalias() = qc * quad.b.row(a).transpose() / dt;   // q̇^a
      if (m > 0) ws.z.tail(m) = u.col(a);
      hessian_by_central_differences(
          ws.z, ws.d, [&](const VecX& z, VecX& g) { force_gradient(model, ws, z, nu.col(a), g); }, ws.Gp, ws.gp, ws.gm,
          ws.Hphi);
      ws.Gp *= quad.w[a] * dt;   // F_d^{k,a} = w^a dt Q
      const auto Hqq_phi = ws.Gp.topLeftCorner(n, n);
      const auto Hvq_phi = ws.Gp.block(n, 0, n, n);
      const auto Hvv_phi = ws.Gp.block(n, n, n, n);
      Hqq.block(a * n, a * n, n, n) += Hqq_phi;
      for (int c = 0; c < S1; ++c) {           // through q̇^a = (1/dt) sum_c b^{ac} q^c
        const double bc = quad.b(a, c) / dt;
        if (bc == 0) continue;
        Hqq.block(c * n, a * n, n, n) += bc * Hvq_phi;
        Hqq.block(a * n, c * n, n, n) += bc * Hvq_phi.transpose();
        for (int d = 0; d < S1; ++d)
          if (quad.b(a, d) != 0) Hqq.block(c * n, d * n, n, n) += (bc * quad.b(a, d) / dt) * Hvv_phi;
      }
      if (m == 0) continue;
      Huq.block(a * m, a * n, m, n) += ws.Gp.block(2 * n, 0, m, n);
      for (int d = 0; d < S1; ++d)
        if (quad.b(a, d) != 0) Huq.block(a * m, d * n, m, n) += (quad.b(a, d) / dt) * ws.Gp.block(2 * n, n, m, n);
      Huu.block(a * m, a * m, m, m) += ws.Gp.bottomRightCorner(m, m);
    }
  }
  ws.Gp = 0.5 * (Hqq + Hqq.transpose());
  Hqq = ws.Gp;
}

}  // namespace hovi
