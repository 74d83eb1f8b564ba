#include "hovi/algorithms/rotation_chart.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace hovi {

Mat3 RotationChart::rotation(const Vec3& theta) const {
  const double ca = std::cos(theta[0]), sa = std::sin(theta[0]), cb = std::cos(theta[1]), sb = std::sin(theta[1]),
               cc = std::cos(theta[2]), sc = std::sin(theta[2]);
  Mat3 R;  // Rz(a) Ry(b) Rx(c)
  R << ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc,
       sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc,
       -sb, cb * sc, cb * cc;
  return R;
}

Mat3 RotationChart::rates_to_omega(const Vec3& theta) const {
  // ω = Rx^T Ry^T z ȧ + Rx^T y ḃ + x ċ
  const double cb = std::cos(theta[1]), sb = std::sin(theta[1]), cc = std::cos(theta[2]), sc = std::sin(theta[2]);
  Mat3 E;
  E << -sb, 0, 1,
       cb * sc, cc, 0,
       cb * cc, -sc, 0;
  return E;
}

Mat3 RotationChart::rates_to_omega_rate(const Vec3& theta, const Vec3& theta_dot) const {
  const double cb = std::cos(theta[1]), sb = std::sin(theta[1]), cc = std::cos(theta[2]), sc = std::sin(theta[2]);
  const double db = theta_dot[1], dc = theta_dot[2];
  Mat3 dE;
  dE << -cb * db, 0, 0,
        -sb * sc * db + cb * cc * dc, -sc * dc, 0,
        -sb * cc * db - cb * sc * dc, -cc * dc, 0;
  return dE;
}

Mat3 RotationChart::centre_shift(const Vec3& theta) const {
  return rates_to_omega(theta).inverse() * rotation(theta).transpose() * rates_to_omega(Vec3::Zero());
}

Mat3 RotationChart::centre_shift_rate(const Vec3& theta, const Vec3& theta_dot) const {
  // A = E^-1 R^T E(0): dA/dt = -E^-1 (Ė A + ω̂ R^T E(0)), with Ṙ^T = -ω̂ R^T and ω = E θ̇
  const Mat3 E = rates_to_omega(theta), Einv = E.inverse();
  const Mat3 RtE0 = rotation(theta).transpose() * rates_to_omega(Vec3::Zero());
  return -Einv * (rates_to_omega_rate(theta, theta_dot) * (Einv * RtE0) + hat(E * theta_dot) * RtE0);
}

Vec3 RotationChart::recentred_momentum(const Vec3& theta, const Vec3& p) const {
  return rates_to_omega(Vec3::Zero()).transpose() * rates_to_omega(theta).transpose().lu().solve(p);
}

Vec3 RotationChart::angles(const Mat3& R) const {
  return Vec3(std::atan2(R(1, 0), R(0, 0)), -std::asin(std::clamp(R(2, 0), -1.0, 1.0)), std::atan2(R(2, 1), R(2, 2)));
}

void RotationChart::recentre_points(int j, const Vec3& theta, Eigen::Ref<MatX> points) const {
  const Mat3 Rt = rotation(theta).transpose();
  for (Eigen::Index a = 0; a < points.cols(); ++a) {
    const Vec3 old = points.col(a).segment<3>(j);
    points.col(a).segment<3>(j) = angles(Rt * rotation(old));
  }
}

Vec3 centre_term(const RotationChart& chart, const Quadrature& quad, double dt, const Eigen::Ref<const MatX>& theta,
                 const Eigen::Ref<const MatX>& theta_dot, const Eigen::Ref<const MatX>& G,
                 const Eigen::Ref<const MatX>& P) {
  const int s = quad.s;
  const Mat3 end = chart.centre_shift(theta.col(s)) - Mat3::Identity();
  Vec3 C = Vec3::Zero();
  for (int a = 0; a <= s; ++a) {
    // Y' vanishes at the ends (A(0) = 1); l_s vanishes at the interior points
    const Mat3 Y = a == 0 || a == s ? Mat3::Zero() : Mat3(chart.centre_shift(theta.col(a)) - Mat3::Identity());
    const Mat3 Ydot = chart.centre_shift_rate(theta.col(a), theta_dot.col(a)) - quad.b(a, s) * end / dt;
    C += quad.w[a] * dt * (Y.transpose() * G.col(a) + Ydot.transpose() * P.col(a));
  }
  return C;
}

}  // namespace hovi
