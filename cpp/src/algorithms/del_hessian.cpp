#include "hovi/algorithms/del_hessian.hpp"

#include <algorithm>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/util/central_differences.hpp"

namespace hovi {

DelHessianWorkspace::DelHessianWorkspace(const Model& model, const Quadrature& quad)
    : jac(model, quad), forces(model), differenced(model), kin_p(model), kin_m(model) {
  differenced.wrenches.clear();
  std::vector<int> bodies;
  for (const auto& w : model.wrenches) {
    PointForce f{w->body(), Vec3::Zero(), Vec3::Zero(), -1};
    if (w->world_point_force(f.point, f.force, f.control)) {
      point_forces.push_back(f);
      continue;
    }
    differenced.wrenches.push_back(w);
    bodies.push_back(w->body());
  }
  moving = model.joints_moving(bodies);
}

namespace {

// (Q_q^T nu, Q_v^T nu, Q_u^T nu) at z = (q, q̇, u): the gradient of nu . Q of the differenced wrenches.
void force_gradient(DelHessianWorkspace& ws, const VecX& z, const Eigen::Ref<const VecX>& nu, VecX& g) {
  const Model& model = ws.differenced;
  const int n = model.n(), m = model.n_controls();
  force_jacobians(model, ws.jac.data, z.head(n), z.segment(n, n), z.tail(m), ws.forces, m > 0);
  g.resize(2 * n + m);
  g.head(n).noalias() = ws.forces.Qq.transpose() * nu;
  g.segment(n, n).noalias() = ws.forces.Qv.transpose() * nu;
  if (m > 0) g.tail(m).noalias() = ws.forces.Qu.transpose() * nu;
}

// The world point forces' part (see the header): per control point a, with H_f = d(J^T f)/dq,
// Hqq^aa += w^a dt sum u_c d/de H_f(q^a + e nu^a) and Huq[u_c, q^a] += w^a dt H_f^T nu^a (H_f the
// mean of its values at q^a +- e nu^a: second order, like the difference).
void point_force_hessian(const Model& model, const Quadrature& quad, DelHessianWorkspace& ws,
                         const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& nu,
                         double dt, Eigen::Ref<MatX> Hqq, Eigen::Ref<MatX> Huq) {
  const int n = model.n(), m = model.n_controls();
  const KinematicsView kp{model, ws.kin_p.g.data(), ws.kin_p.Sbar.data(), 1};
  const KinematicsView km{model, ws.kin_m.g.data(), ws.kin_m.Sbar.data(), 1};
  for (int a = 0; a <= quad.s; ++a) {
    const double size = nu.col(a).cwiseAbs().maxCoeff();
    if (size == 0) continue;
    const double e = kCentralStep * std::max(1.0, qc.col(a).cwiseAbs().maxCoeff()) / size, wdt = quad.w[a] * dt;
    forward_kinematics(model, ws.kin_p, qc.col(a) + e * nu.col(a));
    forward_kinematics(model, ws.kin_m, qc.col(a) - e * nu.col(a));
    ws.Hf.setZero(n, n);
    for (const auto& f : ws.point_forces) {
      ws.Tp.setZero(n, n);
      ws.Tm.setZero(n, n);
      body_point_force_derivative(kp, f.body, f.point, f.force, ws.Tp);
      body_point_force_derivative(km, f.body, f.point, f.force, ws.Tm);
      if (f.control < 0) {
        ws.Hf += ws.Tp - ws.Tm;
        continue;
      }
      ws.Hf += u(f.control, a) * (ws.Tp - ws.Tm);
      Huq.block(a * m + f.control, a * n, 1, n).noalias() += (0.5 * wdt) * ((ws.Tp + ws.Tm).transpose() * nu.col(a)).transpose();
    }
    Hqq.block(a * n, a * n, n, n) += (wdt / (2 * e)) * ws.Hf;
  }
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
  if (!ws.point_forces.empty()) point_force_hessian(model, quad, ws, qc, u, nu, dt, Hqq, Huq);
  if (!ws.differenced.wrenches.empty()) {
    const int Z = 2 * n + m;
    bool velocity = false, control = false;
    for (const auto& w : ws.differenced.wrenches) {
      velocity = velocity || !w->velocity_free();
      control = control || !w->control_affine();
    }
    ws.z.resize(Z);
    ws.d.setOnes(Z);   // 1 where a column is differenced: no wrench moves with a joint off their paths
    ws.d.head(2 * n).setZero();
    for (int j : ws.moving) ws.d[j] = ws.d[n + j] = 1;
    if (!velocity) ws.d.segment(n, n).setZero();
    if (!control) ws.d.tail(m).setZero();
    for (int a = 0; a < S1; ++a) {
      if (nu.col(a).cwiseAbs().maxCoeff() == 0) continue;
      ws.z.head(n) = qc.col(a);
      ws.z.segment(n, n).noalias() = qc * quad.b.row(a).transpose() / dt;   // q̇^a
      if (m > 0) ws.z.tail(m) = u.col(a);
      hessian_by_central_differences(
          ws.z, ws.d, [&](const VecX& z, VecX& g) { force_gradient(ws, z, nu.col(a), g); }, ws.Gp, ws.gp, ws.gm,
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
