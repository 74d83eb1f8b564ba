#include "hovi/algorithms/free_base.hpp"

#include <Eigen/LU>
#include <cmath>
#include <sstream>

#include "hovi/errors.hpp"
#include "hovi/spatial/se3.hpp"

namespace hovi {

namespace {

// log of a rotation: the rotation vector φ with exp(φ^) = R
Vec3 log_rotation(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// The SE(3) logarithm (ω, v) of (R, x): ω = log R, v = V(ω)^-1 x with
// V^-1 = 1 - W/2 + (1 - θ sin θ / (2 (1 - cos θ))) W^2 / θ^2, W = ω^, θ = |ω| (series below 1e-4).
Twist log_se3(const SE3& g) {
  const Vec3 w = log_rotation(g.R);
  const double th = w.norm();
  const double c = th < 1e-4 ? 1.0 / 12 + th * th / 720
                             : (1 - th * std::sin(th) / (2 * (1 - std::cos(th)))) / (th * th);
  const Mat3 W = hat(w);
  Twist out;
  out << w, g.p - 0.5 * W * g.p + c * (W * (W * g.p));
  return out;
}

}  // namespace

Mat3 quaternion_rotation(const Eigen::Ref<const VecX>& xyzw) {
  return Eigen::Quaterniond(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized().toRotationMatrix();
}

Eigen::Vector4d rotation_quaternion(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // one of the two: w >= 0
  return q.coeffs();                        // (x, y, z, w)
}

FreeBase::FreeBase(const Model& model) : j_(model.rotation_chart) {}

void FreeBase::split(const Eigen::Ref<const VecX>& q_pub, Eigen::Ref<VecX> q, Mat3& centre) const {
  const Eigen::Vector4d quat = q_pub.segment<4>(j_);
  if (!(std::abs(quat.norm() - 1) <= 1e-6)) {
    std::ostringstream os;
    os << "q: the base's quaternion (entries " << j_ << " to " << j_ + 3 << ", x y z w) must have norm 1, its norm is "
       << quat.norm();
    throw InputError(os.str());
  }
  centre = quaternion_rotation(quat);
  q.head(j_) = q_pub.head(j_);
  q.segment<3>(j_).setZero();
  q.tail(q.size() - j_ - 3) = q_pub.tail(q.size() - j_ - 3);
}

void FreeBase::join(const Eigen::Ref<const VecX>& q, const Mat3& centre, Eigen::Ref<VecX> q_pub) const {
  q_pub.head(j_) = q.head(j_);
  q_pub.segment<4>(j_) = rotation_quaternion(centre * chart.rotation(q.segment<3>(j_)));
  q_pub.tail(q.size() - j_ - 3) = q.tail(q.size() - j_ - 3);
}

void FreeBase::velocity_to_chart(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const {
  const Vec3 theta = q.segment<3>(j_);
  x.head<3>() = (attitude * x.head<3>()).eval();
  x.segment<3>(j_) = chart.rates_to_omega(theta).lu().solve(Vec3(x.segment<3>(j_)));
}

void FreeBase::velocity_to_public(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const {
  const Vec3 theta = q.segment<3>(j_);
  x.head<3>() = (attitude.transpose() * x.head<3>()).eval();
  x.segment<3>(j_) = (chart.rates_to_omega(theta) * x.segment<3>(j_)).eval();
}

void FreeBase::momentum_to_public(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const {
  const Vec3 theta = q.segment<3>(j_);
  x.head<3>() = (attitude.transpose() * x.head<3>()).eval();
  x.segment<3>(j_) = chart.rates_to_omega(theta).transpose().lu().solve(Vec3(x.segment<3>(j_)));
}

void FreeBase::momentum_to_chart(const Eigen::Ref<const VecX>& q, const Mat3& attitude, Eigen::Ref<VecX> x) const {
  const Vec3 theta = q.segment<3>(j_);
  x.head<3>() = (attitude * x.head<3>()).eval();
  x.segment<3>(j_) = (chart.rates_to_omega(theta).transpose() * x.segment<3>(j_)).eval();
}

void FreeBase::state_to_chart(const Eigen::Ref<const VecX>& q_pub, Eigen::Ref<VecX> q, Mat3& centre,
                              Eigen::Ref<VecX> p) const {
  split(q_pub, q, centre);
  momentum_to_chart(q, centre, p);  // θ = 0: the attitude is the centre
}

void FreeBase::state_to_public(const Eigen::Ref<const VecX>& q, const Mat3& centre, Eigen::Ref<VecX> q_pub,
                               Eigen::Ref<VecX> p) const {
  join(q, centre, q_pub);
  momentum_to_public(q, centre * chart.rotation(q.segment<3>(j_)), p);
}

VecX FreeBase::velocity_rate(const Eigen::Ref<const VecX>& q, const Mat3& attitude,
                             const Eigen::Ref<const VecX>& v) const {
  // d/dt (R_b v_lin) = R_b (ω × v_lin) + R_b v̇_lin; d/dt (E^-1 ω) = E^-1 ω̇ - E^-1 Ė E^-1 ω
  const Vec3 theta = q.segment<3>(j_), omega = v.segment<3>(j_);
  const Mat3 E = chart.rates_to_omega(theta);
  const Vec3 rates = E.lu().solve(omega);
  VecX out = VecX::Zero(v.size());
  out.head<3>() = attitude * omega.cross(Vec3(v.head<3>()));
  out.segment<3>(j_) = -E.lu().solve(chart.rates_to_omega_rate(theta, rates) * rates);
  return out;
}

void FreeBase::tangent_maps(const Mat3& centre, const Eigen::Ref<const VecX>& v, const Eigen::Ref<const VecX>& f,
                            MatX& dq, MatX& dTv, MatX& dTf) const {
  // δ = (δv, δω, δr) moves the chart point by (C δv, E(0)^-1 δω, δr); T = diag(R_b, E(θ)^-1, 1) turns with θ:
  // d(R_b v_lin) = -C v̂_lin δω, d(R_b^T f_x) = (C^T f_x)^ δω, d(E^-1 ω) = -E^-1 dE E^-1 ω, d(E^-T f_θ) likewise.
  const int n = int(v.size()), j = j_, nr = n - j - 3;
  const Mat3 E0inv = chart.rates_to_omega(Vec3::Zero()).inverse();
  dq.setZero(n, n);
  dTv.setZero(n, n);
  dTf.setZero(n, n);
  dq.topLeftCorner(3, 3) = centre;
  dq.block(j, j, 3, 3) = E0inv;
  dq.bottomRightCorner(nr, nr).setIdentity();
  dTv.block(0, j, 3, 3) = -centre * hat(Vec3(v.head<3>()));
  dTf.block(0, j, 3, 3) = hat(Vec3(centre.transpose() * f.head<3>()));
  const Vec3 w = E0inv * v.segment<3>(j), g = E0inv.transpose() * f.segment<3>(j);
  for (int k = 0; k < 3; ++k) {  // dθ = E(0)^-1 δω along column k
    const Mat3 dE = chart.rates_to_omega_rate(Vec3::Zero(), E0inv.col(k));
    dTv.block(j, j + k, 3, 1) = -E0inv * dE * w;
    dTf.block(j, j + k, 3, 1) = -E0inv.transpose() * dE.transpose() * g;
  }
}

VecX FreeBase::integrate(const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& v) const {
  VecX out = q;
  const SE3 M(quaternion_rotation(q.segment<4>(j_)), q.head<3>());
  const SE3 M1 = M * exp_twist((Twist() << v.segment<3>(j_), v.head<3>()).finished(), 1.0);
  out.head<3>() = M1.p;
  out.segment<4>(j_) = rotation_quaternion(M1.R);
  out.tail(out.size() - j_ - 4) += v.tail(v.size() - j_ - 3);
  return out;
}

VecX FreeBase::difference(const Eigen::Ref<const VecX>& q0, const Eigen::Ref<const VecX>& q1) const {
  VecX v(q0.size() - 1);
  const SE3 M0(quaternion_rotation(q0.segment<4>(j_)), q0.head<3>());
  const SE3 M1(quaternion_rotation(q1.segment<4>(j_)), q1.head<3>());
  const Twist t = log_se3(M0.inverse() * M1);
  v.head<3>() = t.tail<3>();
  v.segment<3>(j_) = t.head<3>();
  v.tail(v.size() - j_ - 3) = q1.tail(v.size() - j_ - 3) - q0.tail(v.size() - j_ - 3);
  return v;
}

}  // namespace hovi
