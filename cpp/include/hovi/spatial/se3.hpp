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

// exp(hat(S) q) for a twist S = (omega, v): Rodrigues' formula, exact for any twist.
inline SE3 exp_twist(const Twist& S, double q) {
  const Vec3 w = S.head<3>(), v = S.tail<3>();
  const double th = w.norm();
  if (th < 1e-14) return SE3(Mat3::Identity(), v * q);
  const Vec3 a = w / th;
  const double t = th * q, s = std::sin(t), c = std::cos(t);
  const Mat3 A = hat(a);
  const Mat3 R = Mat3::Identity() + s * A + (1 - c) * A * A;
  // p = (I t + (1-c) A + (t - s) A^2) v / th
  const Mat3 V = Mat3::Identity() * t + (1 - c) * A + (t - s) * A * A;
  return SE3(R, V * v / th);
}

}  // namespace hovi
