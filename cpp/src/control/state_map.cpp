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
  const int n = model.n();
  const FreeBase base(model);
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
  MatX dq, dTv, dTp;
  base.tangent_maps(C, v, pc, dq, dTv, dTp);
  const MatX& Tc = dq;  // at θ = 0 the chart point moves with δ as the velocity map: q̇ = Tc v
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
