// Analytic derivatives of recursive Newton-Euler (Carpentier & Mansard 2018, re-derived in hovi's
// world-frame spatial conventions; the derivation is in the source), O(n^2). Used by the
// Hermite-Simpson baseline and the Hermite-Simpson transcription.
#pragma once
#include <vector>

#include "hovi/model/data.hpp"

namespace hovi {

// Derivatives of inverse dynamics tau = ID(q, v, a) (recursive Newton-Euler, gravity included,
// joint forces NOT included, joint armature included): value, ∂tau/∂q, ∂tau/∂v and ∂tau/∂a = M(q),
// O(n^2).
struct RneaDerivatives {
  explicit RneaDerivatives(const Model& model);
  VecX tau;
  MatX dq, dv, M;
  // Scratch, per body (spatial/world frame)
  std::vector<Twist> v, a, Sdot, psi;  // v̄_i, ā_i (with ā_0 = -g), Ṡ̄_i, ψ_i = ad_{ā_par} S̄_i + ad_{v̄_par} Ṡ̄_i
  std::vector<Wrench> F;               // F̄_i: net wrench transmitted by joint i (subtree sum)
  std::vector<Mat6> Ic, Bc;            // composite inertia and composite B_i = -M̄ ad_v - ad_v^T M̄ - ad^D_{M̄ v}
};
void rnea_derivatives(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                      const Eigen::Ref<const VecX>& v, const Eigen::Ref<const VecX>& a, RneaDerivatives& out);

}  // namespace hovi
