// body_point_jacobian and body_point_force_derivative (algorithms/body_points.hpp) against central
// differences of the point's position and of J(q)^T F, on a branched model with revolute and
// prismatic joints and on the paper's pendulum.
#include <gtest/gtest.h>

#include <random>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/models/pendulum.hpp"
#include "test_models.hpp"

using namespace hovi;
using namespace hovi::test_models;

namespace {

void check_point(const Model& model, int body, const Vec3& r, const VecX& q, const Vec3& F) {
  Data data(model);
  const int n = model.n();
  const KinematicsView kin{model, data.g.data(), data.Sbar.data(), 1};
  auto point = [&](const VecX& x, MatX* J) {
    forward_kinematics(model, data, x);
    Vec3 p;
    MatX Jl = MatX::Zero(3, n);
    body_point_jacobian(kin, body, r, p, Jl);
    if (J) *J = Jl;
    return p;
  };
  MatX J;
  point(q, &J);
  MatX H = MatX::Zero(n, n);
  forward_kinematics(model, data, q);
  body_point_force_derivative(kin, body, r, F, H);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    VecX qp = q, qm = q;
    qp[k] += h;
    qm[k] -= h;
    MatX Jp, Jm;
    const Vec3 dx = (point(qp, &Jp) - point(qm, &Jm)) / (2 * h);
    EXPECT_LE((dx - J.col(k)).cwiseAbs().maxCoeff(), 1e-8) << "dx/dq_" << k;
    const VecX dJF = (Jp.transpose() * F - Jm.transpose() * F) / (2 * h);
    EXPECT_LE((dJF - H.col(k)).cwiseAbs().maxCoeff(), 1e-7) << "d(J^T F)/dq_" << k;
  }
}

}  // namespace

TEST(BodyPoints, JacobianAndForceDerivativeMatchCentralDifferences) {
  std::mt19937 rng(3);
  std::normal_distribution<double> N01;
  const Model pendulum = models::pendulum(6);
  for (int trial = 0; trial < 5; ++trial) {
    VecX q(6);
    for (int i = 0; i < 6; ++i) q[i] = N01(rng);
    check_point(pendulum, 5, Vec3(0.1, -0.05, 0.2), q, Vec3(N01(rng), N01(rng), N01(rng)));
    check_point(pendulum, 3, Vec3(0.0, 0.02, -0.1), q, Vec3(N01(rng), N01(rng), N01(rng)));
  }
  const Model tree = branched_tree();  // revolute and prismatic joints, two branches
  for (int trial = 0; trial < 5; ++trial) {
    const VecX q = uniform(rng, tree.n(), -1.0, 1.0);
    for (int body : {2, 4, 5}) check_point(tree, body, Vec3(0.1, 0.2, -0.3), q, Vec3(N01(rng), N01(rng), N01(rng)));
  }
}
