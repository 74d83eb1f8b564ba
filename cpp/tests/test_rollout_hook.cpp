// A rollout's StepHook (integrators/step_hook.hpp): its controls drive the steps, and a hook without
// controls for a state (or with infinite ones) ends the rollout there, status ControllerFailed, the
// steps before it kept.
#include <gtest/gtest.h>

#include <cmath>

#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

// Controls of 0.5 up to step `stop`; there none (returns false) or, with `overflow`, infinite ones.
class StopsAt : public StepHook {
 public:
  explicit StopsAt(int k, bool overflow = false) : stop_(k), overflow_(overflow) {}
  bool before_step(int k, const VecX&, VecX&, MatX& uk) override {
    uk.setConstant(k >= stop_ && overflow_ ? INFINITY : 0.5);
    return k < stop_ || overflow_;
  }

 private:
  int stop_;
  bool overflow_;
};

}  // namespace

TEST(RolloutHook, AHookWithoutControlsEndsTheRolloutThere) {
  Model model = models::pendulum(3);
  model.add_actuator(0);
  const GalerkinIntegrator integ(model, 2, 0.01);
  const VecX q0 = VecX::Constant(3, 0.2), p0 = VecX::Zero(3);
  StopsAt hook(4);
  const Rollout stopped = integ.rollout(q0, p0, 10, MatX(), StepHistory(), &hook);
  EXPECT_EQ(stopped.steps, 4);
  ASSERT_EQ(stopped.status.size(), 5u);
  EXPECT_EQ(stopped.status.back(), SolveStatus::ControllerFailed);
  StopsAt never(100);
  const Rollout full = integ.rollout(q0, p0, 10, MatX(), StepHistory(), &never);
  EXPECT_EQ(full.steps, 10);
  EXPECT_EQ(stopped.q.topRows(5), full.q.topRows(5));  // the steps before it, as the whole run's
  EXPECT_STREQ(to_string(SolveStatus::ControllerFailed), "controller_failed");
  StopsAt overflows(4, true);  // infinite controls (a feedback that overflowed) end it the same way
  const Rollout inf = integ.rollout(q0, p0, 10, MatX(), StepHistory(), &overflows);
  EXPECT_EQ(inf.steps, 4);
  EXPECT_EQ(inf.status.back(), SolveStatus::ControllerFailed);
}
