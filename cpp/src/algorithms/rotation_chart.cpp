#include "hovi/algorithms/rotation_chart.hpp"

#include <Eigen/LU>

namespace hovi {

namespace {

Mat3 axis_rotation(const Vec3& u, double angle) {
  return exp_twist((Twist() << u, Vec3::Zero()).finished(), angle).R;
}

}  // namespace

RotationChart::RotationChart(const Model& model) {
  for (int k = 0; k < 3; ++k) u[k] = model.spec[model.rotation_chart + k].axis;
}

Mat3 RotationChart::rotation(const Vec3& theta) const {
  return axis_rotation(u[0], theta[0]) * axis_rotation(u[1], theta[1]) * axis_rotation(u[2], theta[2]);
}

Mat3 RotationChart::rates_to_omega(const Vec3& theta) const {
  const Mat3 R2t = axis_rotation(u[1], theta[1]).transpose(), R3t = axis_rotation(u[2], theta[2]).transpose();
  Mat3 E;
  E << R3t * R2t * u[0], R3t * u[1], u[2];
  return E;
}

Mat3 RotationChart::centre_shift(const Vec3& theta) const {
  return rates_to_omega(theta).lu().solve(rotation(theta).transpose() * rates_to_omega(Vec3::Zero()));
}

Mat3 RotationChart::centre_shift_rate(const Vec3& theta, const Vec3& theta_dot) const {
  // A = E^-1 R^T E(0): dA/dt = -E^-1 (Ė A + ω̂ R^T E(0)), with Ṙ^T = -ω̂ R^T, ω = E θ̇ and
  // Ė = θ̇_2 dE/dθ_2 + θ̇_3 dE/dθ_3 (dR_k^T/dθ_k = -û_k R_k^T; E does not depend on θ_1).
  const Mat3 R2t = axis_rotation(u[1], theta[1]).transpose(), R3t = axis_rotation(u[2], theta[2]).transpose();
  const Mat3 E = rates_to_omega(theta);
  Mat3 dE = Mat3::Zero();
  dE.col(0) = -theta_dot[1] * (R3t * hat(u[1]) * R2t * u[0]) - theta_dot[2] * (hat(u[2]) * R3t * R2t * u[0]);
  dE.col(1) = -theta_dot[2] * (hat(u[2]) * R3t * u[1]);
  const Mat3 shift = centre_shift(theta);
  const Mat3 rhs = dE * shift + hat(E * theta_dot) * rotation(theta).transpose() * rates_to_omega(Vec3::Zero());
  return -E.lu().solve(rhs);
}

Vec3 RotationChart::recentred_momentum(const Vec3& theta, const Vec3& p) const {
  return rates_to_omega(Vec3::Zero()).transpose() * rates_to_omega(theta).transpose().lu().solve(p);
}

Vec3 RotationChart::angles(const Mat3& R, Vec3 guess) const {
  for (int it = 0; it < 20; ++it) {
    const Eigen::AngleAxisd aa(rotation(guess).transpose() * R);
    const Vec3 delta = aa.angle() * aa.axis();  // the body-frame rotation left
    guess += rates_to_omega(guess).lu().solve(delta);
    if (delta.norm() < 1e-15) break;
  }
  return guess;
}

void RotationChart::recentre_points(int j, const Vec3& theta, Eigen::Ref<MatX> points) const {
  const Mat3 Rt = rotation(theta).transpose();
  for (Eigen::Index a = 0; a < points.cols(); ++a) {
    const Vec3 old = points.col(a).segment<3>(j);
    points.col(a).segment<3>(j) = angles(Rt * rotation(old), old - theta);
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
