#include "hovi/algorithms/del_residual.hpp"

#include <cassert>

#include "hovi/algorithms/rotation_chart.hpp"

namespace hovi {

void del_residual(const Model& model, const Quadrature& quad, DelWorkspace& ws, const Eigen::Ref<const MatX>& q,
                  const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> r,
                  Eigen::Ref<VecX> p_next) {
  const int n = model.n(), s = quad.s, S1 = s + 1;
  assert(q.rows() == n && q.cols() == S1 && p.size() == n && r.rows() == n && r.cols() == s);
  assert(u.rows() == model.n_controls() && u.cols() == S1);
  ws.dt = dt;
  ws.u = u;
  ws.qdot.noalias() = q.lazyProduct(quad.b.transpose()) / dt;  // q̇_i^a = (1/dt) sum_b b^{ab} q_i^b
  const bool gravity = model.has_gravity();
  const bool wrenches = !model.wrenches.empty();

  // Forward pass: kinematics at every control point; μ̄ and Γ̄ start with the body's own terms.
  for (int i = 0; i < n; ++i) {
    const int par = model.parent[i];
    for (int a = 0; a < S1; ++a) {
      const int k = ws.at(i, a);
      const SE3& g0 = i == model.rotation_chart ? ws.chart_placement : model.g_parent0[i];
      const SE3 gpi = g0 * exp_twist(model.S[i], q(i, a));
      ws.g[k] = par >= 0 ? ws.g[ws.at(par, a)] * gpi : gpi;
      ws.Sbar[k] = Ad(ws.g[k], model.S[i]);
      ws.Mbar[k] = model.M[i].transformed(ws.g[k]);
      ws.v[k] = ws.Sbar[k] * ws.qdot(i, a);
      if (par >= 0) ws.v[k] += ws.v[ws.at(par, a)];
      ws.mu[k] = ws.Mbar[k] * ws.v[k];
      Wrench F = Wrench::Zero();
      if (gravity) {
        F.tail<3>() = model.M[i].m * model.gravity;
        F.head<3>() = ws.g[k].p.cross(F.tail<3>());
      }
      if (wrenches)
        for (const BodyWrench* w : ws.wrenches[i]) F += w->value(ws.g[k], ws.v[k], u.col(a));
      ws.F[k] = quad.w[a] * dt * F;  // discrete impulse F̄_i^{k,a} = w^a dt F̄_i
      ws.Gamma[k] = ws.F[k];
    }
  }

  // Backward pass: accumulate μ̄, Γ̄ over children, then the residual rows of joint i.
  const JointForces& jf = model.joint_forces;
  const bool springs = jf.has_springs(), dampers = jf.has_dampers(), actuated = jf.n_controls() > 0;
  const bool armature = model.has_armature();
  for (int i = n - 1; i >= 0; --i) {
    const int par = model.parent[i];
    double R[32];  // R_i^a, a = 0..s (s <= 16 enforced by Quadrature)
    for (int a = 0; a < S1; ++a) {
      const int k = ws.at(i, a);
      const double wdt = quad.w[a] * dt;
      // Ω̄_i^a = w^a dt ad_{v̄}^T μ̄ + Γ̄   (Prop. 1)
      const Wrench Omega = wdt * adT(ws.v[k], ws.mu[k]) + ws.Gamma[k];
      double Q = 0;  // discrete joint force Q_i^a / (w^a dt)
      if (springs) Q += jf.preload[i] - jf.stiffness[i] * q(i, a);
      if (dampers) Q -= jf.damping[i] * ws.qdot(i, a);
      if (actuated) Q += jf.actuation.row(i).dot(u.col(a));
      R[a] = ws.Sbar[k].dot(Omega) + wdt * Q;
    }
    const int c = i - model.rotation_chart;  // a joint of the rotation chart: c = 0, 1, 2
    const bool charted = model.rotation_chart >= 0 && c >= 0 && c < 3;
    if (charted)
      for (int a = 0; a < S1; ++a) ws.chart_G(c, a) = R[a] / (quad.w[a] * dt);  // dL/dq_i + Q_i at point a
    for (int b = 0; b < S1; ++b) {  // sum_b a^{ab} S̄^b . μ̄^b, the joint momentum (plus a_i q̇_i^b)
      double Smu = ws.Sbar[ws.at(i, b)].dot(ws.mu[ws.at(i, b)]);
      if (armature) Smu += model.armature[i] * ws.qdot(i, b);
      if (charted) ws.chart_P(c, b) = Smu;  // dL/dq̇_i at point b
      for (int a = 0; a < S1; ++a) R[a] += quad.a(a, b) * Smu;
    }
    r(i, 0) = p[i] + R[0];
    for (int a = 1; a < s; ++a) r(i, a) = R[a];
    p_next[i] = R[s];
    if (par >= 0)
      for (int a = 0; a < S1; ++a) {
        ws.mu[ws.at(par, a)] += ws.mu[ws.at(i, a)];
        ws.Gamma[ws.at(par, a)] += ws.Gamma[ws.at(i, a)];
      }
  }
  if (model.rotation_chart >= 0) {  // the chart's centre moves with q^{k,0}: p^k = -D_1 L_d on the group
    const int j = model.rotation_chart;
    r.block<3, 1>(j, 0) += centre_term(RotationChart(), quad, dt, q.middleRows<3>(j), ws.qdot.middleRows<3>(j),
                                        ws.chart_G, ws.chart_P);
  }
}

}  // namespace hovi
