// The flow predictor (flow_predictor.hpp) against closed-form flows: a falling slider and a slider
// driven by a control linear in time (q a cubic in t, which the classical Runge-Kutta step
// integrates exactly), and a slider on a spring (q = q0 cos ωt + v0/ω sin ωt), whose error must
// fall at the method's local order (dt^5) when dt halves; and Newton's converged step from the
// flow guess equal to the step from the default guesses.
#include <gtest/gtest.h>

#include <cmath>

#include "hovi/integrators/flow_predictor.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"

using namespace hovi;

namespace {

// One body of mass m on a prismatic joint along `axis` (world frame), gravity along -z.
Model slider(const Vec3& axis, double m) {
  Model model;
  BodySpec b;
  b.name = "slider";
  b.joint_name = "x";
  b.type = JointType::Prismatic;
  b.axis = axis;
  b.mass = m;
  b.inertia = 0.01 * Mat3::Identity();
  model.add_body(b);
  return model;
}

// The predicted control points (n x (s+1)) from q0, p0 with controls u (m x (s+1)).
MatX predict(const Model& model, int s, double dt, double q0, double p0, const MatX& u) {
  Quadrature quad(s);
  Data data(model);
  FlowPredictor flow(model);
  MatX qc = MatX::Zero(1, s + 1);
  qc(0, 0) = q0;
  VecX p(1);
  p << p0;
  EXPECT_TRUE(flow.predict(model, quad, dt, data, p, u, qc));
  return qc;
}

}  // namespace

TEST(FlowPredictor, FallingSliderIsExact) {
  const Model model = slider(Vec3::UnitZ(), 2.0);
  const double q0 = 0.3, v0 = 0.7, dt = 0.05;
  for (int s = 1; s <= 4; ++s) {
    const MatX qc = predict(model, s, dt, q0, 2.0 * v0, MatX::Zero(0, s + 1));
    const Quadrature quad(s);
    for (int a = 0; a <= s; ++a) {
      const double t = quad.c[a] * dt;
      EXPECT_NEAR(qc(0, a), q0 + v0 * t - 9.81 * t * t / 2, 1e-15) << "s = " << s << ", a = " << a;
    }
  }
}

TEST(FlowPredictor, ControlLinearInTimeIsExact) {
  Model model = slider(Vec3::UnitX(), 0.5);  // horizontal: gravity does no work
  model.add_actuator(0, 2.0);                // Q = 2 u
  const double q0 = -0.1, v0 = 0.4, dt = 0.1, f0 = 1.5, f1 = -0.8;  // u(t) = f0 + f1 t
  for (int s = 1; s <= 4; ++s) {
    const Quadrature quad(s);
    MatX u(1, s + 1);
    for (int a = 0; a <= s; ++a) u(0, a) = f0 + f1 * quad.c[a] * dt;
    const MatX qc = predict(model, s, dt, q0, 0.5 * v0, u);
    for (int a = 0; a <= s; ++a) {
      const double t = quad.c[a] * dt;  // q'' = 2 u / m = 4 (f0 + f1 t)
      EXPECT_NEAR(qc(0, a), q0 + v0 * t + 4 * (f0 * t * t / 2 + f1 * t * t * t / 6), 1e-15) << "s = " << s;
    }
  }
}

TEST(FlowPredictor, SpringSliderConvergesAtFifthOrderPerStep) {
  Model model = slider(Vec3::UnitX(), 1.0);
  model.add_spring(0, 25.0, 0.0);  // ω = 5
  const double q0 = 0.2, v0 = -0.3, w = 5.0;
  for (int s = 1; s <= 5; ++s) {  // s >= 3: fewer steps than intervals, read off the quintic interpolant
    const Quadrature quad(s);
    double previous = 0;
    for (double dt : {0.08, 0.04, 0.02}) {
      const MatX qc = predict(model, s, dt, q0, v0, MatX::Zero(0, s + 1));
      double err = 0;
      for (int a = 1; a <= s; ++a) {
        const double t = quad.c[a] * dt;
        err = std::max(err, std::abs(qc(0, a) - (q0 * std::cos(w * t) + v0 / w * std::sin(w * t))));
      }
      EXPECT_LT(err, 1e-5) << "s = " << s << ", dt = " << dt;
      if (previous > 0) {
        EXPECT_GT(previous / err, 24.0) << "s = " << s << ", dt = " << dt;  // 2^5 = 32
      }
      previous = err;
    }
  }
}

TEST(FlowPredictor, FewerStepsThanIntervalsFromThreeOn) {
  const int expected[] = {0, 1, 2, 2, 3, 4, 4};  // s = 1..6: round(1 / longest interval), at most s
  for (int s = 1; s <= 6; ++s) EXPECT_EQ(FlowPredictor::substeps(Quadrature(s)), expected[s]) << "s = " << s;
}

TEST(FlowPredictor, RolloutsWithEveryPredictorAgree) {
  Model model = slider(Vec3(1, 0, 1), 1.0);
  model.add_spring(0, 40.0, 0.1);
  model.add_damper(0, 0.3);
  const int steps = 50;
  for (int s = 2; s <= 4; ++s) {  // s = 2: one step per interval; 3, 4: the interpolated flow
    MatX last[3];
    const Predictor predictors[3] = {Predictor::History, Predictor::Flow, Predictor::Auto};
    for (int k = 0; k < 3; ++k) {
      SolverOptions opt;
      opt.predictor = predictors[k];
      GalerkinIntegrator integ(model, s, 0.02, opt);
      const Rollout r = integ.rollout((VecX(1) << 0.4).finished(), (VecX(1) << 0.0).finished(), steps, MatX());
      ASSERT_EQ(r.steps, steps);
      last[k] = r.q;
    }
    EXPECT_LT((last[1] - last[0]).cwiseAbs().maxCoeff(), 1e-13) << "s = " << s;
    EXPECT_LT((last[2] - last[0]).cwiseAbs().maxCoeff(), 1e-13) << "s = " << s;
  }
}
