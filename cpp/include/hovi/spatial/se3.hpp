// SE(3) elements g = (R, p) and the exponential of a joint twist (paper Sec. 2.2).
#pragma once
#include <cmath>
#include "hovi/spatial/types.hpp"

namespace hovi {

// hat(w) w2 = w x w2
inline Mat3 hat(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

struct SE3 {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();

  SE3() = default;
  SE3(const Mat3& R_, const Vec3& p_) : R(R_), p(p_) {}
  static SE3 Identity() { return SE3(); }
  static SE3 Translation(const Vec3& t) { return SE3(Mat3::Identity(), t); }

  SE3 operator*(const SE3& o) const { return SE3(R * o.R, R * o.p + p); }
  SE3 inverse() const { return SE3(R.transpose(), -(R.transpose() * p)); }
  Vec3 act(const Vec3& x) const { return R * x + p; }
  Mat4 matrix() const {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = R;
    m.topRightCorner<3, 1>() = p;
    return m;
  }
};

// exp(hat(S) q) for a twist S = (omega, v): Rodrigues' formula, exact for any twist. With
// a = omega / |omega|, A = hat(a) and A^2 = a a^T - 1, theta = |omega| q:
//   R = 1 + sin(theta) A + (1 - cos(theta)) A^2,
//   p = (theta v + (1 - cos(theta)) A v + (theta - sin(theta)) A^2 v) / |omega|,
// evaluated without forming a 3x3 product.
inline SE3 exp_twist(const Twist& S, double q) {
  const Vec3 w = S.head<3>(), v = S.tail<3>();
  const double th = w.norm();
  if (th < 1e-14) return SE3(Mat3::Identity(), v * q);
  const Vec3 a = w / th;
  const double t = th * q, s = std::sin(t), c = std::cos(t), c1 = 1 - c;
  SE3 g;
  g.R.noalias() = c1 * a * a.transpose();
  g.R.diagonal().array() += c;
  const Vec3 sa = s * a;
  g.R(0, 1) -= sa.z(), g.R(1, 0) += sa.z();
  g.R(0, 2) += sa.y(), g.R(2, 0) -= sa.y();
  g.R(1, 2) -= sa.x(), g.R(2, 1) += sa.x();
  const Vec3 axv = a.cross(v);
  const double av = a.dot(v);
  g.p = (s * v + c1 * axv + (t - s) * av * a) / th;  // t v + (t - s)(a (a.v) - v) = s v + (t - s) a (a.v)
  return g;
}

}  // namespace hovi
