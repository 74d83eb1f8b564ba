// The workspace of one step of the Galerkin integrator: per body i and control point a, the
// quantities of Algorithm 1 (kept for the Newton direction, which reuses them). Entry (i, a)
// lives at index i * (s + 1) + a. Sized once; nothing is allocated per call.
#pragma once
#include <vector>

#include "hovi/model/data.hpp"
#include "hovi/quadrature/lobatto.hpp"

namespace hovi {

struct DelWorkspace {
  DelWorkspace(const Model& model, const Quadrature& quad);
  int at(int i, int a) const { return i * (s + 1) + a; }
  // The kinematics of control point a (g, S̄, M̄, v̄) into data, as forward_kinematics(q^{k,a},
  // q̇^{k,a}) would leave them: the D^2 L_d of a step reuses Algorithm 1's forward pass.
  void kinematics_at(int a, Data& data) const;

  int n, s;
  double dt = 0;
  SE3 chart_placement;              // g_{par,j}(0) of the rotation chart's joint j about its centre
  MatX chart_G, chart_P;            // 3 x (s+1): the chart joints' dL/dq + forces and dL/dq̇ at the points
  std::vector<SE3> g;               // g_i^{k,a}
  std::vector<Twist> Sbar;          // S̄_i^{k,a} = Ad_g S_i
  std::vector<Twist> Sdot;          // Ṡ̄_i^{k,a} = ad_{v̄} S̄ (filled by the Newton direction)
  std::vector<SpatialInertia> Mbar; // M̄_i^{k,a}
  std::vector<Twist> v;             // v̄_i^{k,a}
  std::vector<Wrench> mu;           // μ̄_i^{k,a}, discrete articulated-body momentum (Def. 1)
  std::vector<Wrench> F;            // F̄_i^{k,a} = w^a dt F̄_i, discrete impulse on body i
  std::vector<Wrench> Gamma;        // Γ̄_i^{k,a}, discrete articulated-body impulse (Def. 2)
  MatX qdot;                        // q̇_i^{k,a}, n x (s+1)
  MatX u;                           // controls at the control points, m x (s+1)
  std::vector<std::vector<const BodyWrench*>> wrenches;  // the model's wrench elements per body
};

}  // namespace hovi
