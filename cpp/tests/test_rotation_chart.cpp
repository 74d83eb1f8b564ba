// The moving chart of SO(3) (algorithms/rotation_chart.hpp): the chart's kinematics, its first DEL
// residual against differences of the discrete Lagrangian on the group (the chart about its first
// point), and the world momenta of a free-floating chain kept to round-off through steps re-centred
// at every step, at s = 1, 2, 3.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/del_workspace.hpp"
#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/free_base.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/rotation_chart.hpp"
#include "hovi/integrators/dense_direction.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/model/data.hpp"
#include "hovi/parsers/model_serialization.hpp"
#include "test_models.hpp"

using namespace hovi;
using test_models::floating_chain;

namespace {

// Euler angles (z, y, x) of R = Rz(a) Ry(b) Rx(c), near the identity.
Vec3 zyx_angles(const Mat3& R) {
  return Vec3(std::atan2(R(1, 0), R(0, 0)), -std::asin(R(2, 0)), std::atan2(R(2, 1), R(2, 2)));
}

double lagrangian(const Model& m, Data& d, const VecX& q, const VecX& qdot) {
  return kinetic_energy(m, d, q, qdot) - potential_energy(m, d, q);
}

}  // namespace

TEST(RotationChart, RefusesWhatIsNotAChain) {
  Model m = floating_chain(true);
  EXPECT_THROW(m.set_rotation_chart(0), ModelError);  // prismatic joints
  EXPECT_THROW(m.set_rotation_chart(5), ModelError);  // past the end
  EXPECT_NO_THROW(m.set_rotation_chart(3));
}

TEST(RotationChart, PublicStateIsPinocchios) {
  const Model m = floating_chain(true);
  const FreeBase base(m);
  EXPECT_EQ(m.nq(), m.n() + 1);
  VecX q_pub(8);
  q_pub << 0.1, -0.2, 0.3, 0, 0, 0, 1, 0.4;
  q_pub.segment<4>(3) = Eigen::Vector4d(0.3, -0.5, 0.2, 0.7).normalized();
  VecX q(7);
  Mat3 C;
  base.split(q_pub, q, C);
  VecX back(8);
  base.join(q, C, back);
  EXPECT_LT((back - q_pub).norm(), 1e-15);
  // integrate and difference are inverse, and integrate moves the base along its body twist
  VecX v(7);
  v << 0.2, -0.1, 0.4, 0.3, 0.5, -0.7, 0.9;
  const VecX q1 = base.integrate(q_pub, v);
  EXPECT_LT((base.difference(q_pub, q1) - v).norm(), 1e-13);
  const double h = 1e-6;
  const VecX qh = base.integrate(q_pub, h * v);
  EXPECT_LT(((qh.head<3>() - q_pub.head<3>()) / h - C * v.head<3>()).norm(), 1e-6);  // ẋ = R v_lin
  // T^T maps momenta so that p . q̇ = p_v . v: the momentum pairing kept
  VecX p(7), qdot = v, p_pub;
  p << 1.0, 2.0, -0.5, 0.7, -0.3, 0.2, 0.1;
  base.velocity_to_chart(q, C, qdot);
  p_pub = p;
  base.momentum_to_public(q, C, p_pub);
  EXPECT_NEAR(p.dot(qdot), p_pub.dot(v), 1e-14);
  EXPECT_THROW(base.split(VecX::Ones(8), q, C), InputError);  // a quaternion of norm 2
}

// Through the integrator's rollouts (the step re-centres the chart, the record public): the world
// momenta of the free-floating chain in zero gravity, from the public momenta P = R_b p_lin and
// L = x × P + R_b p_ang, kept to round-off; the chart's angles never far from 0.
TEST(RotationChart, RolloutKeepsTheWorldMomenta) {
  for (int s = 1; s <= 3; ++s) {
    const GalerkinIntegrator integ(floating_chain(false), s, s < 3 ? 0.02 : 0.1);
    VecX q0(8), v0(7);
    q0 << 0.1, -0.2, 0.3, 0, 0, 0, 1, 0.4;
    v0 << 0.3, -0.1, 0.2, -1.0, 2.0, 0.05, 0.05;  // about the body's intermediate axis: it flips
    const Rollout r = integ.rollout(q0, integ.momentum(q0, v0), 400, MatX());
    ASSERT_EQ(r.steps, 400);
    double worst = 0;
    Vec3 P0, L0;
    for (int k = 0; k <= 400; ++k) {
      const Mat3 R = quaternion_rotation(r.q.row(k).segment<4>(3).transpose());
      const Vec3 P = R * r.p.row(k).head<3>().transpose();
      const Vec3 L = Vec3(r.q.row(k).head<3>()).cross(P) + R * r.p.row(k).segment<3>(3).transpose();
      if (k == 0) P0 = P, L0 = L;
      worst = std::max({worst, (P - P0).norm() / P0.norm(), (L - L0).norm() / L0.norm()});
      EXPECT_NEAR(r.q.row(k).segment<4>(3).norm(), 1.0, 1e-15);
    }
    EXPECT_LT(worst, 1e-11) << "s = " << s;
    EXPECT_LT(r.iterations.cast<double>().mean(), 8) << "s = " << s;  // a few Newton iterations a step
    std::printf("s = %d: rollout keeps the world momenta to %.1e, %.2f Newton iterations a step\n", s, worst,
                r.iterations.cast<double>().mean());
  }
}

TEST(RotationChart, RolloutTakesThePublicConfiguration) {
  const GalerkinIntegrator integ(floating_chain(false), 1, 0.01);
  EXPECT_THROW(integ.rollout(VecX::Zero(7), VecX::Zero(7), 1, MatX()), InputError);  // q0 must have nq = 8
  VecX q0 = VecX::Zero(8);
  q0[6] = 2;  // a quaternion of norm 2
  EXPECT_THROW(integ.rollout(q0, VecX::Zero(7), 1, MatX()), InputError);
  q0[6] = 1;
  EXPECT_EQ(integ.rollout(q0, VecX::Zero(7), 1, MatX()).q.cols(), 8);
}

TEST(RotationChart, IsKeptBySerialization) {
  const Model m = floating_chain(true);
  EXPECT_EQ(deserialize(serialize(m)).rotation_chart, 3);
  EXPECT_EQ(deserialize(serialize(Model())).rotation_chart, -1);
}

TEST(RotationChart, KinematicsTurnTheBodyAboutTheCentre) {
  const Model m = floating_chain(true);
  const RotationChart chart{};
  Data d(m);
  const Mat3 C = chart.rotation(Vec3(0.7, -1.1, 2.0));
  d.chart_placement = m.chart_placement(C);
  VecX q = VecX::Zero(m.n());
  q << 0.1, -0.2, 0.3, 0.2, 0.3, -0.4, 0.5;
  forward_kinematics(m, d, q);
  EXPECT_LT((d.g[5].R - C * chart.rotation(q.segment<3>(3))).norm(), 1e-14);
  EXPECT_LT((d.g[5].p - (q.head<3>() + C * chart.rotation(q.segment<3>(3)) * m.spec[5].com)).norm(), 1e-14);
  // E(θ): the body's angular velocity from the rates, against the kinematics
  const Vec3 theta = q.segment<3>(3), rates(0.3, -0.2, 0.5);
  const double h = 1e-6;
  const Mat3 dR = (chart.rotation(theta + h * rates) - chart.rotation(theta - h * rates)) / (2 * h);
  const Mat3 W = chart.rotation(theta).transpose() * dR;
  EXPECT_LT((Vec3(W(2, 1), W(0, 2), W(1, 0)) - chart.rates_to_omega(theta) * rates).norm(), 1e-9);
  // the chart's inverse: angles(R(θ)) = θ (|θ_2| < π/2), in closed form
  EXPECT_LT((chart.angles(chart.rotation(theta)) - theta).norm(), 1e-14);
  // dA/dt against differences of A along θ(t) = θ + t θ̇
  const Mat3 dA = (chart.centre_shift(theta + h * rates) - chart.centre_shift(theta - h * rates)) / (2 * h);
  EXPECT_LT((chart.centre_shift_rate(theta, rates) - dA).norm(), 1e-8);
}

// s = 1: L_d(g0, g1) = dt/2 (L(q^0, q̇) + L(q^1, q̇)) in the chart about g0's attitude; the first residual
// with p = 0 is D_1 L_d, also along the chart (the centre moves with g0), by central differences.
TEST(RotationChart, FirstResidualIsTheGroupDerivativeOfTheDiscreteLagrangian) {
  const Model m = floating_chain(true);
  const RotationChart chart{};
  const Quadrature quad(1);
  const double dt = 0.05;
  const int n = m.n();
  Data d(m);
  DelWorkspace ws(m, quad);
  const Mat3 C0 = chart.rotation(Vec3(0.4, 0.9, -0.3));  // the start's attitude
  MatX qc(n, 2);
  qc.col(0) << 0.1, -0.2, 0.3, 0, 0, 0, 0.4;
  qc.col(1) << 0.12, -0.19, 0.27, 0.03, -0.05, 0.04, 0.43;
  const Mat3 R1 = C0 * chart.rotation(qc.col(1).segment<3>(3));  // the end's attitude, held
  auto Ld = [&](const Mat3& centre, const VecX& q0, const VecX& q1_world) {
    VecX q1 = q1_world;
    q1.segment<3>(3) = zyx_angles(centre.transpose() * R1);
    const VecX qdot = (q1 - q0) / dt;
    d.chart_placement = m.chart_placement(centre);
    return dt / 2 * (lagrangian(m, d, q0, qdot) + lagrangian(m, d, q1, qdot));
  };
  MatX r(n, 1);
  VecX p_next(n);
  ws.chart_placement = m.chart_placement(C0);
  del_residual(m, quad, ws, qc, VecX::Zero(n), MatX::Zero(0, 2), dt, r, p_next);
  const double h = 1e-6;
  for (int i = 0; i < n; ++i) {
    double D1;
    if (i >= 3 && i < 6) {  // along the chart: the start's attitude C0 R_i(δ), the centre with it
      VecX e = VecX::Zero(3);
      e[i - 3] = h;
      D1 = (Ld(C0 * chart.rotation(e), qc.col(0), qc.col(1)) - Ld(C0 * chart.rotation(-e), qc.col(0), qc.col(1))) /
           (2 * h);
    } else {
      VecX e = VecX::Zero(n);
      e[i] = h;
      D1 = (Ld(C0, qc.col(0) + e, qc.col(1)) - Ld(C0, qc.col(0) - e, qc.col(1))) / (2 * h);
    }
    EXPECT_NEAR(r(i, 0), D1, 1e-8 * (1 + std::abs(D1))) << "joint " << i;
  }
}

// Zero gravity: L_d on the group is invariant under the world's translations and rotations, so the
// DEL steps keep the linear momentum p_xyz and the angular momentum x × p_xyz + C E(0)^-T p_θ about
// the origin through large turns, while the chart stays near θ = 0: to 1e-11 over 400 steps (the
// residuals' floor, about 1e-14 a step), where the chart's step without the centre's term (the
// chart held fixed while a step is taken) drifts at O(dt^2s).
double momentum_drift(int s, bool group) {
  const Model m = floating_chain(false);
  const RotationChart chart{};
  const Quadrature quad(s);
  const double dt = s < 3 ? 0.02 : 0.1;  // s = 3: a step whose O(dt^6) shows above round-off
  const int n = m.n();
  Data d(m);
  DelWorkspace ws(m, quad);
  VecX q = VecX::Zero(n), qdot(n);
  q << 0.1, -0.2, 0.3, 0, 0, 0, 0.4;
  qdot << 0.3, -0.1, 0.2, 0.05, 2.0, 0.05, -1.0;  // spun about the intermediate axis (it flips)
  Mat3 C = Mat3::Identity();
  d.chart_placement = m.chart_placement(C);
  forward_kinematics(m, d, q, qdot);
  VecX p(n);
  {  // p = M(q) q̇ through the kinetic energy's gradient in q̇ (central differences of a quadratic: exact)
    for (int i = 0; i < n; ++i) {
      VecX e = VecX::Zero(n);
      e[i] = 1e-3;
      p[i] = (kinetic_energy(m, d, q, qdot + e) - kinetic_energy(m, d, q, qdot - e)) / 2e-3;
    }
  }
  const Mat3 E0 = chart.rates_to_omega(Vec3::Zero());
  auto momenta = [&](const VecX& q, const Mat3& C, const VecX& p) {
    const Vec3 P = p.head<3>();
    const Vec3 L = q.head<3>().cross(P) + C * E0.transpose().lu().solve(Vec3(p.segment<3>(3)));
    return std::make_pair(P, L);
  };
  const auto [P0, L0] = momenta(q, C, p);
  MatX qc(n, s + 1), r(n, s);
  VecX p_next(n);
  const MatX u = MatX::Zero(0, s + 1);
  double turned = 0, worst = 0;
  for (int k = 0; k < 400; ++k) {
    ws.chart_placement = m.chart_placement(C);
    for (int a = 0; a <= s; ++a) qc.col(a) = q + quad.c[a] * dt * qdot;  // a guess from the last velocity
    auto residual = [&](const MatX& points) {  // the group's DEL residual, or the fixed chart's
      del_residual(m, quad, ws, points, p, u, dt, r, p_next);
      if (!group)
        r.block<3, 1>(3, 0) -= centre_term(chart, quad, dt, points.middleRows<3>(3), ws.qdot.middleRows<3>(3),
                                           ws.chart_G, ws.chart_P);
      return VecX(Eigen::Map<const VecX>(r.data(), r.size()));
    };
    for (int it = 0; it < 30; ++it) {  // Newton on the unknown points, the Jacobian by differences
      const VecX r0 = residual(qc);
      MatX J(n * s, n * s);
      for (int col = 0; col < n * s; ++col) {
        MatX qp = qc, qm = qc;
        qp(col % n, 1 + col / n) += 1e-7;
        qm(col % n, 1 + col / n) -= 1e-7;
        J.col(col) = (residual(qp) - residual(qm)) / 2e-7;
      }
      const VecX dx = J.lu().solve(-r0);
      for (int col = 0; col < n * s; ++col) qc(col % n, 1 + col / n) += dx[col];
      if (dx.lpNorm<Eigen::Infinity>() < 1e-15 * (1 + qc.lpNorm<Eigen::Infinity>())) break;
    }
    EXPECT_LT(residual(qc).lpNorm<Eigen::Infinity>(), 1e-12) << "step " << k;
    const Vec3 theta = qc.col(s).segment<3>(3);
    qdot = (qc.col(s) - qc.col(s - 1)) / (dt * (quad.c[s] - quad.c[s - 1]));
    qdot.segment<3>(3) = chart.rates_to_omega(Vec3::Zero()).lu().solve(chart.rates_to_omega(theta) * qdot.segment<3>(3));
    C = C * chart.rotation(theta);  // re-centre: θ = 0 about the new attitude, the momentum lifted
    p = p_next;
    p.segment<3>(3) = chart.recentred_momentum(theta, p_next.segment<3>(3));
    q = qc.col(s);
    q.segment<3>(3).setZero();
    turned += theta.norm();
    const auto [P, L] = momenta(q, C, p);
    worst = std::max({worst, (P - P0).lpNorm<Eigen::Infinity>() / P0.norm(), (L - L0).lpNorm<Eigen::Infinity>() / L0.norm()});
  }
  EXPECT_GT(turned, 10.0);  // radians: large turns, each step near the chart's centre
  return worst;
}

class RotationChartMomentum : public ::testing::TestWithParam<int> {};

TEST_P(RotationChartMomentum, FreeFloatingChainKeepsItsMomentaToRoundOff) {
  const int s = GetParam();
  const double group = momentum_drift(s, true), fixed = momentum_drift(s, false);
  EXPECT_LT(group, 1e-11) << "s = " << s;
  EXPECT_GT(fixed, 100 * group) << "s = " << s;  // measured: the fixed chart's drift
  std::printf("s = %d: momenta kept to %.1e on the group, %.1e in the fixed chart\n", s, group, fixed);
}

INSTANTIATE_TEST_SUITE_P(Orders, RotationChartMomentum, ::testing::Values(1, 2, 3));

// The Newton direction of a free base against the direction of the whole residual's Jacobian by
// central differences, at ω dt = 0.08: the dense one at s >= 2 has the chart term's derivative
// (add_centre_term_jacobian, exact_chart_direction) and is exact to the differences' accuracy; the
// others leave it out and are off by 2.6e-5 (s = 1) to 1.4e-3 (s = 2, 3), the contraction of their
// Newton iteration.
TEST(RotationChart, NewtonDirectionOnBothPaths) {
  for (const Direction path : {Direction::Dense, Direction::Recursive})
    for (int s = 1; s <= 3; ++s) {
      const Model m = floating_chain(true);
      SolverOptions options;
      options.direction = path;
      const GalerkinIntegrator integ(m, s, 0.05, options);
      const int n = m.n();
      MatX qc(n, s + 1);
      VecX qdot(n);
      qdot << 0.3, -0.1, 0.2, 1.5, -1.0, 0.8, -0.7;
      qc.col(0) << 0.1, -0.2, 0.3, 0, 0, 0, 0.4;
      integ.guess_from_velocity(qdot, qc);
      qc.rightCols(s) += 1e-3 * MatX::Ones(n, s);  // off the solution: a residual to correct
      const VecX p = VecX::LinSpaced(n, 0.5, -0.3);
      const MatX u = MatX::Zero(0, s + 1);
      MatX r(n, s), dq(n, s);
      VecX p_next(n);
      integ.residual(qc, p, u, r, p_next);
      ASSERT_TRUE(integ.direction(qc, p, u, dq));
      MatX J(n * s, n * s);
      for (int col = 0; col < n * s; ++col) {
        MatX qp = qc, qm = qc, rp(n, s), rm(n, s);
        qp(col % n, 1 + col / n) += 1e-6;
        qm(col % n, 1 + col / n) -= 1e-6;
        integ.residual(qp, p, u, rp, p_next);
        integ.residual(qm, p, u, rm, p_next);
        J.col(col) = (Eigen::Map<const VecX>(rp.data(), rp.size()) - Eigen::Map<const VecX>(rm.data(), rm.size())) / 2e-6;
      }
      const VecX rv = Eigen::Map<const VecX>(r.data(), r.size());
      const VecX exact = -J.lu().solve(rv);
      const double error = (Eigen::Map<const VecX>(dq.data(), dq.size()) - exact).norm() / exact.norm();
      const bool with_term = exact_chart_direction(path, m, s);
      std::printf("s = %d, %s: the Newton direction within %.1e of the differenced Jacobian's\n", s,
                  path == Direction::Dense ? "dense" : "recursive", error);
      EXPECT_LT(error, with_term ? 1e-8 : 3e-3) << "s = " << s;
    }
}
