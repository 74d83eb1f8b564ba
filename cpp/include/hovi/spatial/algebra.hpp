// Adjoint operators on se(3) and its dual (paper Sec. 2.2) and spatial inertias.
#pragma once
#include "hovi/spatial/se3.hpp"

namespace hovi {

// Ad_g = [R 0; p^R R]: body twist -> spatial twist
inline Mat6 Ad(const SE3& g) {
  Mat6 m;
  m.topLeftCorner<3, 3>() = g.R;
  m.topRightCorner<3, 3>().setZero();
  m.bottomLeftCorner<3, 3>() = hat(g.p) * g.R;
  m.bottomRightCorner<3, 3>() = g.R;
  return m;
}
inline Twist Ad(const SE3& g, const Twist& v) {
  Twist out;
  out.head<3>() = g.R * v.head<3>();
  out.tail<3>() = g.p.cross(out.head<3>()) + g.R * v.tail<3>();
  return out;
}
// Ad_g^{-T}: body wrench -> spatial wrench
inline Wrench AdInvT(const SE3& g, const Wrench& F) {
  Wrench out;
  out.tail<3>() = g.R * F.tail<3>();
  out.head<3>() = g.R * F.head<3>() + g.p.cross(out.tail<3>());
  return out;
}
// ad_v = [w^ 0; v^ w^]
inline Mat6 ad(const Twist& v) {
  Mat6 m;
  m.topLeftCorner<3, 3>() = hat(v.head<3>());
  m.topRightCorner<3, 3>().setZero();
  m.bottomLeftCorner<3, 3>() = hat(v.tail<3>());
  m.bottomRightCorner<3, 3>() = m.topLeftCorner<3, 3>();
  return m;
}
// ad_{v1} v2 without forming the matrix
inline Twist ad(const Twist& v1, const Twist& v2) {
  Twist out;
  out.head<3>() = v1.head<3>().cross(v2.head<3>());
  out.tail<3>() = v1.tail<3>().cross(v2.head<3>()) + v1.head<3>().cross(v2.tail<3>());
  return out;
}
// ad_v^T F without forming the matrix
inline Wrench adT(const Twist& v, const Wrench& F) {
  Wrench out;
  out.head<3>() = -v.head<3>().cross(F.head<3>()) - v.tail<3>().cross(F.tail<3>());
  out.tail<3>() = -v.head<3>().cross(F.tail<3>());
  return out;
}
// ad^D_F = [tau^ f^; f^ 0], so that F^T ad_{v1} v2 = v2^T ad^D_F v1
inline Mat6 adD(const Wrench& F) {
  Mat6 m;
  m.topLeftCorner<3, 3>() = hat(F.head<3>());
  m.topRightCorner<3, 3>() = hat(F.tail<3>());
  m.bottomLeftCorner<3, 3>() = m.topRightCorner<3, 3>();
  m.bottomRightCorner<3, 3>().setZero();
  return m;
}

// A spatial inertia about a frame's origin: mass m, first moment h = m c, and rotational
// inertia I about the origin. As a 6x6 matrix [I h^; -h^ m 1] acting on (omega, v).
struct SpatialInertia {
  double m = 0;
  Vec3 h = Vec3::Zero();
  Mat3 I = Mat3::Zero();

  SpatialInertia() = default;
  SpatialInertia(double m_, const Vec3& h_, const Mat3& I_) : m(m_), h(h_), I(I_) {}
  // The body inertia M_i = blockdiag(I_c, m 1) of a body whose frame sits at its centre of mass.
  static SpatialInertia AtCom(double m, const Mat3& Ic) { return SpatialInertia(m, Vec3::Zero(), Ic); }

  Wrench operator*(const Twist& v) const {
    Wrench out;
    out.head<3>() = I * v.head<3>() + h.cross(v.tail<3>());
    out.tail<3>() = m * v.tail<3>() - h.cross(v.head<3>());
    return out;
  }
  SpatialInertia& operator+=(const SpatialInertia& o) {
    m += o.m;
    h += o.h;
    I += o.I;
    return *this;
  }
  Mat6 matrix() const {
    Mat6 M;
    M.topLeftCorner<3, 3>() = I;
    M.topRightCorner<3, 3>() = hat(h);
    M.bottomLeftCorner<3, 3>() = -hat(h);
    M.bottomRightCorner<3, 3>() = m * Mat3::Identity();
    return M;
  }
  // Ad_g^{-T} M Ad_g^{-1}: the same body's inertia expressed in the frame g maps into. With
  // h_R = R h and hat(a) hat(b) = b a^T - (a.b) 1, the rotational inertia about the new origin,
  //   R I R^T - (p^ h_R^ + h_R^ p^) - m p^ p^
  //     = R I R^T + (2 p.h_R + m |p|^2) 1 - h_R p^T - p h_R^T - m p p^T,
  // is symmetric: only its upper triangle is computed.
  SpatialInertia transformed(const SE3& g) const {
    const Vec3& p = g.p;
    const Vec3 hr = g.R * h;
    const Mat3 RI = g.R * I;
    const Vec3 k = hr + 0.5 * m * p;  // h_R p^T + p h_R^T + m p p^T = k p^T + p k^T
    const double d = 2 * p.dot(hr) + m * p.squaredNorm();
    SpatialInertia out;
    out.m = m;
    out.h = hr + m * p;
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) {
        const double x = RI.row(r).dot(g.R.row(c)) - k[r] * p[c] - p[r] * k[c];
        out.I(r, c) = out.I(c, r) = r == c ? x + d : x;
      }
    return out;
  }
};

}  // namespace hovi
