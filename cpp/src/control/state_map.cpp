#include "hovi/control/state_map.hpp"

#include <Eigen/Cholesky>

#include <Eigen/LU>

#include "hovi/algorithms/free_base.hpp"
#include "hovi/algorithms/kinetic_hessians.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/spatial/se3.hpp"

namespace hovi {

namespace {
// A free base: v = M_v(q)^-1 p with M_v = T^T M T the mass matrix of the public velocity (T the
// chart's velocity map, FreeBase), so dv/dδ|_p = -M_v^-1 dp/dδ|_v for a tangent δ. In the chart about
// q's attitude C (θ = 0) δ moves the chart point by dq = (C δv, E(0)^-1 δω, δr), and
// p(δ) = T(θ)^T p_c(q, T(θ) v): dp/dδ = d(T^T) p_c + T^T (Kvq dq + M d(T) v), d(T) through θ only.
void free_base_state_map(const Model& model, Data& data, const Eigen::Ref<const VecX>& q_pub,
                         const Eigen::Ref<const VecX>& p, MatX& T) {
  const int n = model.n(), j = model.rotation_chart, nr = n - j - 3;
  const FreeBase base(model);
  const RotationChart& chart = base.chart;
  VecX q(n), pc = p;
  Mat3 C;
  base.split(q_pub, q, C);
  data.chart_placement = model.chart_placement(C);
  base.momentum_to_chart(q, C, pc);
  const MatX M = mass_matrix(model, data, q);
  const VecX qdot = Eigen::LLT<MatX>(M).solve(pc);
  VecX v = qdot;
  base.velocity_to_public(q, C, v);
  kinetic_hessians(model, data, q, qdot);  // Kvq = dp_c/dq at fixed q̇
  const Mat3 E0 = chart.rates_to_omega(Vec3::Zero()), E0inv = E0.inverse();
  MatX dq = MatX::Zero(n, n), dTv = MatX::Zero(n, n), dTp = MatX::Zero(n, n);  // by δ
  dq.topLeftCorner(3, 3) = C;
  dq.block(j, j, 3, 3) = E0inv;
  dq.bottomRightCorner(nr, nr).setIdentity();
  dTv.block(0, j, 3, 3) = -C * hat(Vec3(v.head<3>()));  // d(R_b v_lin) = -C v̂_lin δω
  const Vec3 p_lin = C.transpose() * pc.head<3>(), w_ang = E0inv.transpose() * pc.segment<3>(j);
  dTp.block(0, j, 3, 3) = hat(p_lin);  // d(R_b^T p_x) = p̂_lin δω
  for (int k = 0; k < 3; ++k) {  // dθ = E(0)^-1 δω along column k of E(0)^-1
    const Vec3 dth = E0inv.col(k);
    const Mat3 dE = chart.rates_to_omega_rate(Vec3::Zero(), dth);
    dTv.block(j, j + k, 3, 1) = -E0inv * dE * E0inv * v.segment<3>(j);
    dTp.block(j, j + k, 3, 1) = -E0inv.transpose() * dE.transpose() * w_ang;
  }
  MatX Tc = MatX::Identity(n, n);  // the chart's velocity map at θ = 0: q̇ = Tc v
  Tc.topLeftCorner(3, 3) = C;
  Tc.block(j, j, 3, 3) = E0inv;
  const MatX Mv = Tc.transpose() * M * Tc;
  const MatX dp = dTp + Tc.transpose() * (data.Kvq * dq + M * dTv);
  const Eigen::LLT<MatX> lv(Mv);
  T.setZero(2 * n, 2 * n);
  T.topLeftCorner(n, n).setIdentity();
  T.bottomLeftCorner(n, n) = -lv.solve(dp);
  T.bottomRightCorner(n, n) = lv.solve(MatX::Identity(n, n));
}
}  // namespace

void velocity_state_map(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                        const Eigen::Ref<const VecX>& p, MatX& T) {
  if (model.rotation_chart >= 0) return free_base_state_map(model, data, q, p, T);
  const int n = model.n();
  const MatX M = mass_matrix(model, data, q);
  const Eigen::LLT<MatX> llt(M);
  const VecX qdot = llt.solve(p);
  kinetic_hessians(model, data, q, qdot);  // Kvv = M (armature included), Kvq = dp/dq at fixed q̇
  const Eigen::LLT<MatX> lv(data.Kvv);
  T.setZero(2 * n, 2 * n);
  T.topLeftCorner(n, n).setIdentity();
  T.bottomLeftCorner(n, n) = -lv.solve(data.Kvq);
  T.bottomRightCorner(n, n) = lv.solve(MatX::Identity(n, n));
}

}  // namespace hovi
