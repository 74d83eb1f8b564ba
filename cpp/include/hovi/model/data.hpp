// The per-call workspace of the rigid-body algorithms (Pinocchio's Model/Data split): sized
// once for a model, reused across calls so that hot functions allocate nothing.
#pragma once
#include <vector>

#include "hovi/model/model.hpp"

namespace hovi {

struct Data {
  explicit Data(const Model& model);

  SE3 chart_placement;                 // g_{par,j}(0) of the rotation chart's joint j about its centre
  std::vector<SE3> g;                  // g_i, pose of body frame {i} (at the COM) in {0}
  std::vector<Twist> Sbar;             // S̄_i = Ad_{g_i} S_i, spatial joint twist
  std::vector<SpatialInertia> Mbar;    // M̄_i = Ad_{g_i}^{-T} M_i Ad_{g_i}^{-1}
  std::vector<Twist> v;                // v̄_i, spatial velocity
  std::vector<Twist> Sdot;             // Ṡ̄_i = ad_{v̄_i} S̄_i
  std::vector<Wrench> mu;              // μ̄_i, articulated-body momentum (Def. 1)
  // Scratch of the dynamics algorithms
  std::vector<Twist> a;                // spatial acceleration dv̄_i/dt
  std::vector<Twist> c;                // velocity-product acceleration Ṡ̄_i q̇_i
  std::vector<Mat6> IA;                // articulated-body inertia (ABA) / composite inertia (CRBA)
  std::vector<Wrench> pA;              // articulated-body bias wrench / RNEA joint wrench
  std::vector<Wrench> U;               // IA_i S̄_i
  VecX D, u;                           // S̄_i^T IA_i S̄_i and tau_i - S̄_i^T pA_i
  VecX qdd, tau;                       // outputs of forward / inverse dynamics
  MatX Mq;                             // joint-space mass matrix M(q)
  MatX Kvv, Kvq, Kqv, Kqq, Vqq;        // second derivatives of K and V_g (Algorithms 2, 3)
  VecX sigma_m;                        // σ_m,i: mass of the subtree of i (Algorithm 3)
  std::vector<Vec3> sigma_p;           // σ_p,i: sum of m_j p_j over the subtree of i (Algorithm 3)
};

}  // namespace hovi
