// Batched rollouts, steps and linearisations (batch.hpp) give, item by item and bit for bit, the
// single calls made one after another, on 1 and 3 threads; a failed solve is an item's status.
#include <gtest/gtest.h>

#include <random>

#include "test_models.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/batch.hpp"

using namespace hovi;

namespace {

constexpr int kStates = 12, kSteps = 30;

struct Fixture {
  GalerkinIntegrator integ{test_models::forced_pendulum(), 2, 0.01};
  MatX q, v, u;
  Fixture() {
    std::mt19937 rng(7);
    const int n = integ.model().n(), m = integ.model().n_controls();
    q.resize(kStates, n);
    v.resize(kStates, n);
    for (int b = 0; b < kStates; ++b) {
      q.row(b) = test_models::uniform(rng, n, -1, 1).transpose();
      v.row(b) = test_models::uniform(rng, n, -2, 2).transpose();
    }
    v.row(kStates - 1).setConstant(1e4);  // a state whose first step fails
    u.resize(kStates * kSteps, 3 * m);
    for (int r = 0; r < u.rows(); ++r) u.row(r) = test_models::uniform(rng, 3 * m, -1, 1).transpose();
  }
};

}  // namespace

TEST(Batch, RolloutsAreTheSingleRollouts) {
  Fixture x;
  for (int threads : {1, 3}) {
    const RolloutBatch r = rollout_batch(x.integ, {x.q, x.v, true}, kSteps, x.u, threads);
    for (int b = 0; b < kStates; ++b) {
      ASSERT_TRUE(r.errors[b].empty()) << r.errors[b];
      const Rollout one = x.integ.rollout(x.q.row(b).transpose(), x.integ.momentum(x.q.row(b).transpose(), x.v.row(b).transpose()),
                                          kSteps, x.u.middleRows(b * kSteps, kSteps));
      EXPECT_EQ(r.items[b].steps, one.steps);
      EXPECT_EQ(r.items[b].status, one.status);
      EXPECT_EQ(r.items[b].q.topRows(one.steps + 1), one.q.topRows(one.steps + 1));
      EXPECT_EQ(r.items[b].control_points.topRows(one.steps), one.control_points.topRows(one.steps));
    }
    EXPECT_EQ(r.items[kStates - 1].steps, 0);  // failed, and the batch went on
    EXPECT_EQ(r.items[0].steps, kSteps);
  }
}

TEST(Batch, StepsAreTheSingleSteps) {
  Fixture x;
  const int n = x.integ.model().n();
  const MatX u = x.u.topRows(kStates);
  const StepBatch r = step_batch(x.integ, {x.q, x.v, true}, u, 3);
  for (int b = 0; b < kStates; ++b) {
    MatX qc(n, 3);
    qc.col(0) = x.q.row(b).transpose();
    VecX p_next(n);
    const MatX ub = Eigen::Map<const MatX>(MatX(u.row(b)).data(), x.integ.model().n_controls(), 3);
    StepHistory h;
    const SolveInfo info =
        x.integ.step(x.integ.momentum(x.q.row(b).transpose(), x.v.row(b).transpose()), ub, qc, p_next, h);
    EXPECT_EQ(r.items[b].info.status, info.status);
    EXPECT_EQ(r.items[b].info.iterations, info.iterations);
    EXPECT_EQ(r.items[b].qc, qc);
    EXPECT_EQ(r.items[b].p_next, p_next);
  }
}

TEST(Batch, TrajectoryJacobiansAreTheSingleOnes) {
  Fixture x;
  const int n = x.integ.model().n(), m = x.integ.model().n_controls(), B = kStates - 1;
  const RolloutBatch r = rollout_batch(x.integ, {x.q.topRows(B), x.v.topRows(B), true}, kSteps, x.u.topRows(B * kSteps), 2);
  MatX C(B * kSteps, 3 * n);
  for (int b = 0; b < B; ++b) C.middleRows(b * kSteps, kSteps) = r.items[b].control_points;
  const Linearizer lin(x.integ);
  std::vector<double> As(std::size_t(B) * kSteps * 4 * n * n), Bs(std::size_t(B) * kSteps * 2 * n * 3 * m);
  const auto errors = trajectory_jacobians_batch(lin, B, kSteps, C, x.u.topRows(B * kSteps), MatX(), As.data(), Bs.data(), 0, 3);
  std::vector<double> A1(std::size_t(kSteps) * 4 * n * n), B1(std::size_t(kSteps) * 2 * n * 3 * m);
  for (int b = 0; b < B; ++b) {
    ASSERT_EQ(errors[b], "");
    ASSERT_EQ(lin.trajectory_jacobians(r.items[b].control_points, x.u.middleRows(b * kSteps, kSteps), MatX(), A1.data(),
                                       B1.data()),
              -1);
    EXPECT_TRUE(std::equal(A1.begin(), A1.end(), As.begin() + b * A1.size()));
    EXPECT_TRUE(std::equal(B1.begin(), B1.end(), Bs.begin() + b * B1.size()));
  }
}

TEST(Batch, BadInputThrows) {
  Fixture x;
  const MatX none(0, x.integ.model().n());
  EXPECT_THROW(rollout_batch(x.integ, {none, none, true}, 3, MatX()), InputError);
  EXPECT_THROW(rollout_batch(x.integ, {x.q, x.v.topRows(2), true}, 3, MatX()), InputError);
  EXPECT_THROW(rollout_batch(x.integ, {x.q, x.v, true}, -1, MatX()), InputError);
  EXPECT_THROW(rollout_batch(x.integ, {x.q, x.v, true}, kSteps, x.u.topRows(5)), InputError);
  EXPECT_THROW(step_batch(x.integ, {x.q, x.v, true}, x.u), InputError);
  EXPECT_THROW(rollout_batch(x.integ, {x.q, x.v, true}, kSteps, x.u, -2), InputError);
}
