// A model's base rotation as a moving chart of SO(3) (Model::set_rotation_chart): joints j..j+2 turn
// the body by R(θ) = Rz(θ_1) Ry(θ_2) Rx(θ_3) about a centre C, its attitude C R(θ). A step starts
// at θ = 0 about the attitude it starts from, so no step comes near the chart's singularity, and
// its discrete Lagrangian is the one of the chart about its first point, L_d(R_0, R_1). That makes it
// the variational integrator on the group: its first DEL equation, p^k = -D_1 L_d, moves the chart's
// centre with R_0, which adds centre_term to the first residual (docs/how-it-works.md, "The free
// base"; measured in bench/README.md, "Free bodies on SE(3)").
#pragma once
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/model/model.hpp"
#include "hovi/quadrature/lobatto.hpp"

namespace hovi {

// The chart is Z-Y-X: R(θ) = Rz(θ_1) Ry(θ_2) Rx(θ_3) (Model::set_rotation_chart checks the axes).
struct RotationChart {
  Mat3 rotation(const Vec3& theta) const;        // R(θ)
  // E(θ): the body's angular velocity (in its own frame) = E(θ) θ̇
  Mat3 rates_to_omega(const Vec3& theta) const;
  Mat3 rates_to_omega_rate(const Vec3& theta, const Vec3& theta_dot) const;  // dE/dt along θ(t)
  // A(θ) = E(θ)^-1 R(θ)^T E(0): how coordinates θ about C R(δ) move about C as δ leaves 0
  Mat3 centre_shift(const Vec3& theta) const;
  Mat3 centre_shift_rate(const Vec3& theta, const Vec3& theta_dot) const;  // dA/dt along θ(t)
  // The momentum p (3,) of the chart's joints at θ, carried to the chart about C R(θ) at θ = 0:
  // the cotangent lift E(0)^T E(θ)^-T p of the change of coordinates.
  Vec3 recentred_momentum(const Vec3& theta, const Vec3& p) const;
  // θ with R(θ) = R, |θ_2| <= π/2 (a step's points lie within a fraction of that of the centre).
  Vec3 angles(const Mat3& R) const;
  // Control points (n x (s+1), the chart's rows j..j+2) in the chart about C, re-expressed in the
  // chart about C R(θ): each point's attitude kept.
  void recentre_points(int j, const Vec3& theta, Eigen::Ref<MatX> points) const;
};

// The chart's term of a step's first DEL residual rows (the chart's joints). The action's derivative
// along how the step's path moves in the fixed chart when its centre moves with the start is
//   sum_a w^a dt [G^a . Y^a + P^a . Ẏ^a],  Y(t) = A(θ(t)) - l_0(t) 1 - l_s(t) A(θ^s),
// G = dL/dq + the joint forces and P = dL/dq̇ at the points. Its part along Y - Y' = sum of the interior
// l_b(t) 1 is the sum of the chart's interior DEL equations, which vanish at the solution; C keeps the
// rest, Y'(t) = A(θ(t)) - 1 - l_s(t) (A(θ^s) - 1) = O(θ): the step's equations have the same
// solution and C's derivative is small: the joints' DEL Jacobian without it (the recursive direction)
// gives a Newton direction off by about 1e-3 (docs/how-it-works.md); add_centre_term_jacobian gives it.
// From the chart joints' θ, θ̇ (3 x (s+1)), G and P at the points.
Vec3 centre_term(const RotationChart& chart, const Quadrature& quad, double dt, const Eigen::Ref<const MatX>& theta,
                 const Eigen::Ref<const MatX>& theta_dot, const Eigen::Ref<const MatX>& G,
                 const Eigen::Ref<const MatX>& P);

// centre_term's derivative added to the chart's rows of r^{k,0} in Jq (and Ju, if given): from the step's
// DEL rows r (n x s, its interior columns used), the chart joints' dL/dq̇ P (3 x (s+1)) and ws's Kvq, Kvv at
// the control points qc (ws: del_jacobian's at qc). Jq holds the column blocks col0..s of del_jacobian.hpp's
// layout (1: the Newton direction's window). A's second derivative by central differences of its closed form.
void add_centre_term_jacobian(const Model& model, const Quadrature& quad, double dt, const Eigen::Ref<const MatX>& qc,
                              const MatX& r, const MatX& P, const DelJacobianWorkspace& ws, Eigen::Ref<MatX> Jq,
                              MatX* Ju = nullptr, int col0 = 0);

}  // namespace hovi
