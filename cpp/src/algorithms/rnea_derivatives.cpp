#include "hovi/algorithms/rnea_derivatives.hpp"

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

// ---------------------------------------------------------------------------------------------
// Derivatives of recursive Newton-Euler in spatial coordinates. With ā_0 = -g (gravity as a base
// acceleration, equivalent to the wrench F̄_i = [m p̂ g; m g]),
//   v̄_i = v̄_par + S̄_i q̇_i,  ā_i = ā_par + Ṡ̄_i q̇_i + S̄_i q̈_i,  Ṡ̄_i = ad_{v̄_par} S̄_i,
//   f̄_i = M̄_i ā_i - ad_{v̄_i}^T M̄_i v̄_i,  F̄_i = f̄_i + Σ_chd F̄_j,  tau_i = S̄_i^T F̄_i.
// A change of q_l rotates the subtree of l about S̄_l; apart from that rigid motion (under which
// tau is invariant) v̄ and ā of a body j in the subtree change by Ṡ̄_l and ψ_l - ad_{v̄_j} Ṡ̄_l,
// ψ_l = ad_{ā_par(l)} S̄_l + ad_{v̄_par(l)} Ṡ̄_l, so δf̄_j = M̄_j ψ_l + B_j Ṡ̄_l with
// B_j = -M̄_j ad_{v̄_j} - ad_{v̄_j}^T M̄_j - ad^D_{M̄_j v̄_j}. Likewise ∂v̄_j/∂q̇_l = S̄_l and
// ∂ā_j/∂q̇_l = 2 Ṡ̄_l - ad_{v̄_j} S̄_l, so ∂f̄_j/∂q̇_l = 2 M̄_j Ṡ̄_l + B_j S̄_l. Summing over subtrees
// with Ic_i = Σ M̄_j and Bc_i = Σ B_j:
//   l ∈ anc(i) ∪ {i}:  ∂tau_i/∂q_l = S̄_i^T (Ic_i ψ_l + Bc_i Ṡ̄_l),
//                      ∂tau_i/∂q̇_l = S̄_i^T (2 Ic_i Ṡ̄_l + Bc_i S̄_l),    M_il = S̄_i^T Ic_i S̄_l,
//   i ∈ anc(l):        ∂tau_i/∂q_l = S̄_i^T (-ad_{S̄_l}^T F̄_l + Ic_l ψ_l + Bc_l Ṡ̄_l),
//                      ∂tau_i/∂q̇_l = S̄_i^T (2 Ic_l Ṡ̄_l + Bc_l S̄_l),    M_il = S̄_i^T Ic_l S̄_l,
// and zero between different branches.
// ---------------------------------------------------------------------------------------------

RneaDerivatives::RneaDerivatives(const Model& model)
    : tau(model.n()), dq(model.n(), model.n()), dv(model.n(), model.n()), M(model.n(), model.n()),
      v(model.n()), a(model.n()), Sdot(model.n()), psi(model.n()), F(model.n()), Ic(model.n()), Bc(model.n()) {}

void rnea_derivatives(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& qdot, const Eigen::Ref<const VecX>& qddot, RneaDerivatives& out) {
  forward_kinematics(model, data, q);
  check_vector("qdot", qdot, model.n());
  check_vector("qddot", qddot, model.n());
  const int n = model.n();
  Twist a_base;  // ā_0 = -g
  a_base << 0, 0, 0, -model.gravity;
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    const Twist vp = p >= 0 ? out.v[p] : Twist::Zero();
    const Twist ap = p >= 0 ? out.a[p] : a_base;
    const Twist& S = data.Sbar[i];
    out.Sdot[i] = ad(vp, S);                               // Ṡ̄_i = ad_{v̄_par} S̄_i
    out.v[i] = vp + S * qdot[i];                           // v̄_i
    out.a[i] = ap + out.Sdot[i] * qdot[i] + S * qddot[i];  // ā_i
    out.psi[i] = ad(ap, S) + ad(vp, out.Sdot[i]);          // ψ_i
    const SpatialInertia& Mb = data.Mbar[i];
    const Wrench mu = Mb * out.v[i];                        // μ̄_i = M̄_i v̄_i
    out.F[i] = Mb * out.a[i] - adT(out.v[i], mu);          // f̄_i
    out.Ic[i] = Mb.matrix();
    // X = M̄ ad_v = [[I ŵ + ĥ û, ĥ ŵ], [m û - ĥ ŵ, m ŵ]] (v = (w, u), M̄ = [[I, ĥ], [-ĥ, m 1]])
    const Mat3 W = hat(out.v[i].head<3>()), U = hat(out.v[i].tail<3>()), H = hat(Mb.h);
    const Mat3 HW = H * W;
    Mat6 X;
    X.topLeftCorner<3, 3>().noalias() = Mb.I * W + H * U;
    X.topRightCorner<3, 3>() = HW;
    X.bottomLeftCorner<3, 3>() = Mb.m * U - HW;
    X.bottomRightCorner<3, 3>() = Mb.m * W;
    out.Bc[i] = -(X + X.transpose()) - adD(mu);            // B_i = -M̄ ad_v - ad_v^T M̄ - ad^D_μ
  }
  for (int i = n - 1; i >= 0; --i) {  // subtree sums F̄_i, Ic_i, Bc_i
    const int p = model.parent[i];
    if (p < 0) continue;
    out.F[p] += out.F[i];
    out.Ic[p] += out.Ic[i];
    out.Bc[p] += out.Bc[i];
  }
  out.dq.setZero();
  out.dv.setZero();
  out.M.setZero();
  for (int i = 0; i < n; ++i) {
    const Twist& Si = data.Sbar[i];
    out.tau[i] = Si.dot(out.F[i]);
    const Wrench IS = out.Ic[i] * Si;                  // (S̄_i^T Ic_i)^T
    const Wrench BS = out.Bc[i].transpose() * Si;      // (S̄_i^T Bc_i)^T
    for (int l = i; l >= 0; l = model.parent[l]) {     // l ∈ anc(i) ∪ {i}
      out.dq(i, l) = IS.dot(out.psi[l]) + BS.dot(out.Sdot[l]);
      out.dv(i, l) = 2 * IS.dot(out.Sdot[l]) + BS.dot(data.Sbar[l]);
      out.M(i, l) = IS.dot(data.Sbar[l]);
    }
    const Wrench wq = -adT(Si, out.F[i]) + out.Ic[i] * out.psi[i] + out.Bc[i] * out.Sdot[i];
    const Wrench wv = 2 * (out.Ic[i] * out.Sdot[i]) + out.Bc[i] * Si;
    for (int j = model.parent[i]; j >= 0; j = model.parent[j]) {  // j ∈ anc(i): column i
      out.dq(j, i) = data.Sbar[j].dot(wq);
      out.dv(j, i) = data.Sbar[j].dot(wv);
      out.M(j, i) = IS.dot(data.Sbar[j]);
    }
  }
  if (model.has_armature()) {  // tau += diag(a) q̈: nothing in dq, dv
    out.tau += model.armature.cwiseProduct(qddot);
    out.M.diagonal() += model.armature;
  }
}

}  // namespace hovi
