// A model's free base (Model::set_rotation_chart) in Pinocchio's conventions for its free flyer, so
// that states pass between hovi and Pinocchio unchanged. The public configuration q (nq = n + 1)
// holds the base's position (x, y, z) and its attitude as a unit quaternion (qx, qy, qz, qw) where the
// chart holds three angles; a velocity v (n) the base's linear and angular velocity in its own frame;
// a momentum p_v the conjugate of v, p_v = T^T p for q̇ = T v (docs/how-it-works.md, "The free
// base"). Inside a step the base turns in the chart: angles θ about a centre C, its attitude C R(θ).
#pragma once
#include "hovi/algorithms/rotation_chart.hpp"

namespace hovi {

class FreeBase {
 public:
  explicit FreeBase(const Model& model);  // the model must have a free base

  // Public q (nq) -> chart q (n) with θ = 0 about the centre C = the attitude. Throws InputError
  // unless the quaternion's norm is 1 to 1e-6 (it is normalised).
  void split(const Eigen::Ref<const VecX>& q_pub, Eigen::Ref<VecX> q, Mat3& centre) const;
  // Chart q (n, any θ) about C -> public q (nq).
  void join(const Eigen::Ref<const VecX>& q, const Mat3& centre, Eigen::Ref<VecX> q_pub) const;
  // In place at chart q (angles θ) where the base's attitude is R_b: a velocity v -> q̇ = T v
  // (to_chart) or q̇ -> v; a momentum p -> T^T p (to_public) or back. T = diag(R_b, E(θ)^-1, 1).
  void velocity_to_chart(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const;
  void velocity_to_public(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const;
  void momentum_to_public(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const;
  void momentum_to_chart(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const;
  // Ṫ v, so that q̈ = T a + Ṫ v for an acceleration a (the derivative of v).
  VecX velocity_rate(const Eigen::Ref<const VecX>& q, const Mat3& attitude, const Eigen::Ref<const VecX>& v) const;
  // At the chart's point about C (θ = 0) for a tangent δ of q (q ⊕ δ): dq = d(chart q)/dδ, and for a velocity v
  // and a chart covector f (a momentum or a force) dTv = d(T v)/dδ and dTf = d(T^T f)/dδ (n x n each):
  // what a quantity q -> T^T g(q, T v) differentiates to, T^T (g_q dq + g_v dTv) + dTf with f = g.
  void tangent_maps(const Mat3& centre, const Eigen::Ref<const VecX>& v, const Eigen::Ref<const VecX>& f, MatX& dq,
                    MatX& dTv, MatX& dTf) const;
  int joint() const { return j_; }

  // A whole state: public (q_pub: nq; p in place) -> the chart about q's attitude (q: n with θ = 0,
  // its centre), and a chart state (q: n, any θ, about centre; p in place) -> public (q_pub: nq).
  void state_to_chart(const Eigen::Ref<const VecX>& q_pub, Eigen::Ref<VecX> q, Mat3& centre, Eigen::Ref<VecX> p) const;
  void state_to_public(const Eigen::Ref<const VecX>& q, const Mat3& centre, Eigen::Ref<VecX> q_pub,
                       Eigen::Ref<VecX> p) const;

  // Pinocchio's integrate and difference: the base by the group, q ⊕ v = (M exp(v)) with M = (R, x),
  // and v = log(M_0^-1 M_1); the other joints by addition. q: nq, v: n.
  VecX integrate(const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& v) const;
  VecX difference(const Eigen::Ref<const VecX>& q0, const Eigen::Ref<const VecX>& q1) const;

  const RotationChart chart{};

 private:
  int j_;  // the chart's first joint (3)
};

// Unit quaternion (x, y, z, w) <-> rotation matrix.
Mat3 quaternion_rotation(const Eigen::Ref<const VecX>& xyzw);
Eigen::Vector4d rotation_quaternion(const Mat3& R);

}  // namespace hovi
