// Recursive algorithms against independent computations: M(q) against the Hessian of the
// kinetic energy in q̇, ABA against a dense solve with RNEA, RNEA against M q̈ + RNEA(q̈ = 0).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "test_models.hpp"
#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/errors.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

void check_model(const Model& model) {
  Data data(model);
  const int n = model.n();
  for (int trial = 0; trial < 3; ++trial) {
    const VecX q = VecX::Random(n), qd = VecX::Random(n), tau = VecX::Random(n);
    const MatX M = mass_matrix(model, data, q);
    // K is quadratic in q̇: M_ij = K(e_i + e_j) - K(e_i) - K(e_j) exactly.
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const VecX ei = VecX::Unit(n, i), ej = VecX::Unit(n, j);
        const double Mij = kinetic_energy(model, data, q, ei + ej) - kinetic_energy(model, data, q, ei) -
                           kinetic_energy(model, data, q, ej);
        EXPECT_NEAR(M(i, j), Mij, 1e-11 * (1 + M.norm()));
      }
    const VecX bias = inverse_dynamics(model, data, q, qd, VecX::Zero(n));
    const VecX qdd_dense = M.ldlt().solve(tau - bias);
    const VecX qdd = forward_dynamics(model, data, q, qd, tau);
    EXPECT_LT((qdd - qdd_dense).norm(), 1e-10 * (1 + qdd.norm()));
    const VecX tau_back = inverse_dynamics(model, data, q, qd, qdd);
    EXPECT_LT((tau_back - tau).norm(), 1e-10 * (1 + tau.norm()));
    EXPECT_LT((inverse_dynamics(model, data, q, qd, qdd) - (M * qdd + bias)).norm(), 1e-10 * (1 + tau.norm()));
  }
}
}  // namespace

TEST(Dynamics, PendulumMatchesDenseReferences) { check_model(models::pendulum(6)); }
TEST(Dynamics, BranchedTreeMatchesDenseReferences) { check_model(test_models::branched_tree()); }

// The bias of RNEA at rest is the gradient of the potential energy (central differences).
TEST(Dynamics, GravityTorqueIsPotentialGradient) {
  const Model model = test_models::branched_tree();
  Data data(model);
  const VecX q = VecX::Random(model.n());
  const VecX G = inverse_dynamics(model, data, q, VecX::Zero(model.n()), VecX::Zero(model.n()));
  for (int i = 0; i < model.n(); ++i) {
    const double h = 1e-6;
    const VecX e = VecX::Unit(model.n(), i) * h;
    const double dV = (potential_energy(model, data, q + e) - potential_energy(model, data, q - e)) / (2 * h);
    EXPECT_NEAR(G[i], dV, 1e-7);
  }
}

TEST(Dynamics, MasslessJointIsReported) {
  Model m;
  BodySpec s;
  s.name = "ghost";
  s.joint_name = "ghost_joint";
  m.add_body(s);
  Data data(m);
  EXPECT_THROW(forward_dynamics(m, data, VecX::Zero(1), VecX::Zero(1), VecX::Zero(1)), ModelError);
}

TEST(Dynamics, WrongSizesAndNaNAreRejected) {
  const Model model = models::pendulum(3);
  Data data(model);
  EXPECT_THROW(mass_matrix(model, data, VecX::Zero(2)), InputError);
  VecX q = VecX::Zero(3);
  q[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(mass_matrix(model, data, q), InputError);
}
