#include "hovi/algorithms/rotation_chart.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include "hovi/util/central_differences.hpp"

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

namespace {
// The chart at one point θ: E, E^-1, A and E's rates along the axes, so that A's rate along any θ̇ is 3 x 3
// algebra (no trigonometry): Ȧ = -E^-1 (Ė A + (E θ̇)^ R^T E(0)).
struct ChartPoint {
  ChartPoint(const RotationChart& chart, const Vec3& theta) {
    E = chart.rates_to_omega(theta);
    Einv = E.inverse();
    RtE0 = chart.rotation(theta).transpose() * chart.rates_to_omega(Vec3::Zero());
    A = Einv * RtE0;
    for (int k = 0; k < 3; ++k) dE[k] = chart.rates_to_omega_rate(theta, Vec3::Unit(k));
  }
  Mat3 rate(const Vec3& v) const {
    return -Einv * ((v[0] * dE[0] + v[1] * dE[1] + v[2] * dE[2]) * A + hat(E * v) * RtE0);
  }
  Mat3 E, Einv, RtE0, A, dE[3];
};
}  // namespace

void add_centre_term_jacobian(const Model& model, const Quadrature& quad, double dt, const Eigen::Ref<const MatX>& qc,
                              const MatX& r, const MatX& P, const DelJacobianWorkspace& ws, Eigen::Ref<MatX> Jq,
                              MatX* Ju, int col0) {
  // With Y' = 0 at the ends, C = sum_b Y'_b^T r^b + sum_a w^a dt D_a^T P_a, D_a = Ẏ'_a - sum_b b^{ab} Y'_b / dt
  // (r^b the interior DEL rows): dC from the rows of Jq and Ju, dP_a = Kvq(a) dq^a + sum_c b^{ac} / dt
  // Kvv(a) dq^c, and A's derivatives.
  const RotationChart chart;
  const int n = model.n(), s = quad.s, S1 = s + 1, j = model.rotation_chart;
  const auto th = qc.middleRows(j, 3);
  const MatX thd = th * quad.b.transpose() / dt;
  std::vector<ChartPoint> pt;
  pt.reserve(S1);
  for (int a = 0; a < S1; ++a) pt.emplace_back(chart, th.col(a));
  std::vector<Mat3> Y(S1, Mat3::Zero()), D(S1), dA(3 * S1);  // dA[3a + k] = dA(θ^a)/dθ_k
  for (int b = 1; b < s; ++b) Y[b] = pt[b].A - Mat3::Identity();
  const Mat3 end = pt[s].A - Mat3::Identity();
  for (int a = 0; a < S1; ++a) {
    D[a] = pt[a].rate(thd.col(a)) - quad.b(a, s) * end / dt;
    for (int b = 1; b < s; ++b) D[a] -= quad.b(a, b) * Y[b] / dt;
    for (int k = 0; k < 3; ++k) dA[3 * a + k] = pt[a].rate(Vec3::Unit(k));
  }
  const int cols = (S1 - col0) * n;  // Jq holds the column blocks col0..s
  MatX dC = MatX::Zero(3, cols);
  for (int b = 1; b < s; ++b) dC.noalias() += Y[b].transpose() * Jq.block(b * n + j, 0, 3, cols);
  for (int a = 0; a < S1; ++a) {
    if (a >= col0)
      dC.block(0, (a - col0) * n, 3, n).noalias() += (quad.w[a] * dt) * D[a].transpose() * ws.Kvq[a].middleRows(j, 3);
    for (int c = col0; c < S1; ++c)
      if (quad.b(a, c) != 0)
        dC.block(0, (c - col0) * n, 3, n).noalias() +=
            (quad.w[a] * quad.b(a, c)) * D[a].transpose() * ws.Kvv[a].middleRows(j, 3);
  }
  // the chart's own columns: Y' and D move with θ (A's second derivative by central differences of its closed form)
  for (int c = col0; c < S1; ++c)
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = Vec3::Unit(k);
      const Mat3& dAc = dA[3 * c + k];
      const Mat3 dAdot = (ChartPoint(chart, th.col(c) + kCentralStep * e).rate(thd.col(c)) -
                          ChartPoint(chart, th.col(c) - kCentralStep * e).rate(thd.col(c))) /
                         (2 * kCentralStep);  // d/dθ_k of Ȧ(θ^c, θ̇^c) at fixed θ̇
      Vec3 col = Vec3::Zero();
      if (c > 0 && c < s) col += dAc.transpose() * r.col(c).segment<3>(j);
      for (int a = 0; a < S1; ++a) {
        Mat3 dD = (quad.b(a, c) / dt) * dA[3 * a + k];
        if (a == c) dD += dAdot;
        if (c == s) dD -= (quad.b(a, s) / dt) * dAc;
        if (c > 0 && c < s) dD -= (quad.b(a, c) / dt) * dAc;
        col += (quad.w[a] * dt) * dD.transpose() * P.col(a);
      }
      dC.col((c - col0) * n + j + k) += col;
    }
  Jq.block(j, 0, 3, cols) += dC;
  if (Ju && Ju->cols() > 0) {
    MatX dCu = MatX::Zero(3, Ju->cols());
    for (int b = 1; b < s; ++b) dCu.noalias() += Y[b].transpose() * Ju->block(b * n + j, 0, 3, Ju->cols());
    Ju->middleRows(j, 3) += dCu;
  }
}

}  // namespace hovi
