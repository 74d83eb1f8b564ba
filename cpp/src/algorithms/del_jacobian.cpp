#include "hovi/algorithms/del_jacobian.hpp"

#include "hovi/algorithms/gravity_hessian.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/kinetic_hessians.hpp"

namespace hovi {

DelJacobianWorkspace::DelJacobianWorkspace(const Model& model, const Quadrature& quad)
    : data(model), forces(model), Kvv(quad.s + 1, MatX(model.n(), model.n())), Kvq(Kvv), Kqv(Kvv), Kqq(Kvv),
      Vqq(Kvv), qdot(model.n(), quad.s + 1) {}

namespace {
// The window's block counts resolved against s + 1 blocks.
BlockWindow resolved(BlockWindow w, int S1) {
  if (w.rows < 0) w.rows = S1 - w.row0;
  if (w.cols < 0) w.cols = S1 - w.col0;
  return w;
}
bool contains(const BlockWindow& w, int b, int c) {
  return b >= w.row0 && b < w.row0 + w.rows && c >= w.col0 && c < w.col0 + w.cols;
}
}  // namespace

void dlagrangian_hessian(const Model& model, const Quadrature& quad, DelJacobianWorkspace& ws,
                         const Eigen::Ref<const MatX>& qc, double dt, Eigen::Ref<MatX> D2Ld,
                         const DelWorkspace* kinematics, BlockWindow window) {
  const int n = model.n(), S1 = quad.s + 1;
  const BlockWindow win = resolved(window, S1);
  const VecX& w = quad.w;
  const MatX& b = quad.b;
  ws.qdot.noalias() = qc.lazyProduct(b.transpose()) / dt;  // coefficient-wise: no temporary
  const bool gravity = model.has_gravity();
  for (int a = 0; a < S1; ++a) {
    if (kinematics) kinematics->kinematics_at(a, ws.data);
    else forward_kinematics(model, ws.data, qc.col(a), ws.qdot.col(a));
    kinetic_hessians(model, ws.data);
    // Swapped, not copied: both algorithms overwrite their outputs in full.
    ws.Kvv[a].swap(ws.data.Kvv);
    ws.Kvq[a].swap(ws.data.Kvq);
    ws.Kqv[a].swap(ws.data.Kqv);
    ws.Kqq[a].swap(ws.data.Kqq);
    if (gravity && contains(win, a, a)) {  // V_g enters the diagonal blocks only
      gravity_hessian(model, ws.data);
      ws.Vqq[a].swap(ws.data.Vqq);
    }
  }
  for (int bb = win.row0; bb < win.row0 + win.rows; ++bb)
    for (int c = win.col0; c < win.col0 + win.cols; ++c) {
      auto blk = D2Ld.block((bb - win.row0) * n, (c - win.col0) * n, n, n);
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
                  MatX* Ju, const DelWorkspace* kinematics, BlockWindow window) {
  const int n = model.n(), m = model.n_controls(), S1 = quad.s + 1;
  const BlockWindow win = resolved(window, S1);
  dlagrangian_hessian(model, quad, ws, qc, dt, Jq, kinematics, win);
  const bool joint = model.joint_forces.any(), wrenches = !model.wrenches.empty();
  if (Ju) Ju->setZero(S1 * n, S1 * m);
  if (!joint && !wrenches) return;  // no non-conservative forces: nothing more to add
  auto block = [&](int a, int c) { return Jq.block((a - win.row0) * n, (c - win.col0) * n, n, n); };
  for (int a = 0; a < S1; ++a) {
    const bool row = a >= win.row0 && a < win.row0 + win.rows;
    if (!row && !Ju) continue;
    const double wdt = quad.w[a] * dt;
    force_jacobians(model, ws.data, qc.col(a), ws.qdot.col(a), u.col(a), ws.forces, Ju != nullptr);
    if (contains(win, a, a)) block(a, a) += wdt * ws.forces.Qq;
    for (int c = 0; c < S1; ++c)
      if (quad.b(a, c) != 0 && contains(win, a, c)) block(a, c) += (quad.w[a] * quad.b(a, c)) * ws.forces.Qv;
    if (Ju && m > 0) Ju->block(a * n, a * m, n, m) = wdt * ws.forces.Qu;
  }
}

}  // namespace hovi
