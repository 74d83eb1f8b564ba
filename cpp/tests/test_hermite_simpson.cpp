// The Hermite-Simpson collocation baseline: RNEA derivatives against finite differences, the
// collocation conditions at the solution, the order of convergence against an RK4 reference,
// input checks and failure reporting.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "test_models.hpp"
#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/baselines/hermite_simpson.hpp"
#include "hovi/errors.hpp"
#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

using test_models::forced_pendulum;
using test_models::uniform;

// ẋ = f(x) = (v, FD(q, v, preload - k q - c v + B u)) with a constant control u (empty: none).
void rhs(const Model& model, Data& data, const VecX& u, const VecX& q, const VecX& v, VecX& qd, VecX& vd) {
  const JointForces& jf = model.joint_forces;
  VecX tau = jf.preload - jf.stiffness.cwiseProduct(q) - jf.damping.cwiseProduct(v);
  if (u.size()) tau += jf.actuation * u;
  qd = v;
  vd = forward_dynamics(model, data, q, v, tau);
}

// Classical RK4 with N equal steps over [0, T]; returns q(T) (v(T) in v_out).
VecX rk4(const Model& model, VecX q, VecX v, double T, int N, VecX* v_out = nullptr, const VecX& u = VecX()) {
  Data data(model);
  const double h = T / N;
  const int n = model.n();
  VecX k1q(n), k1v(n), k2q(n), k2v(n), k3q(n), k3v(n), k4q(n), k4v(n);
  for (int k = 0; k < N; ++k) {
    rhs(model, data, u, q, v, k1q, k1v);
    rhs(model, data, u, q + 0.5 * h * k1q, v + 0.5 * h * k1v, k2q, k2v);
    rhs(model, data, u, q + 0.5 * h * k2q, v + 0.5 * h * k2v, k3q, k3v);
    rhs(model, data, u, q + h * k3q, v + h * k3v, k4q, k4v);
    q += (h / 6) * (k1q + 2 * k2q + 2 * k3q + k4q);
    v += (h / 6) * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  if (v_out) *v_out = v;
  return q;
}

void check_rnea_derivatives(const Model& model, std::mt19937& rng) {
  const int n = model.n();
  Data data(model);
  RneaDerivatives d(model);
  for (int trial = 0; trial < 3; ++trial) {
    const VecX q = uniform(rng, n, -1, 1), v = uniform(rng, n, -2, 2), a = uniform(rng, n, -3, 3);
    rnea_derivatives(model, data, q, v, a, d);
    const VecX tau = inverse_dynamics(model, data, q, v, a);
    EXPECT_LT((d.tau - tau).cwiseAbs().maxCoeff(), 1e-12 * (1 + tau.cwiseAbs().maxCoeff()));
    const MatX M = mass_matrix(model, data, q);
    EXPECT_LT((d.M - M).cwiseAbs().maxCoeff(), 1e-13 * (1 + M.cwiseAbs().maxCoeff()));
    // 4th-order central differences of RNEA.
    MatX Dq(n, n), Dv(n, n);
    const double e = 1e-3;
    for (int j = 0; j < n; ++j) {
      auto fd = [&](auto tau_at) {
        return VecX((8 * (tau_at(e) - tau_at(-e)) - (tau_at(2 * e) - tau_at(-2 * e))) / (12 * e));
      };
      Dq.col(j) = fd([&](double s) { return VecX(inverse_dynamics(model, data, q + s * VecX::Unit(n, j), v, a)); });
      Dv.col(j) = fd([&](double s) { return VecX(inverse_dynamics(model, data, q, v + s * VecX::Unit(n, j), a)); });
    }
    EXPECT_LT((d.dq - Dq).cwiseAbs().maxCoeff(), 1e-9 * (1 + Dq.cwiseAbs().maxCoeff())) << d.dq << "\n\n" << Dq;
    EXPECT_LT((d.dv - Dv).cwiseAbs().maxCoeff(), 1e-9 * (1 + Dv.cwiseAbs().maxCoeff())) << d.dv << "\n\n" << Dv;
  }
}

}  // namespace

TEST(HermiteSimpson, RneaDerivativesMatchFiniteDifferences) {
  std::mt19937 rng(1);
  check_rnea_derivatives(models::pendulum(5), rng);
  check_rnea_derivatives(test_models::branched_tree(), rng);
}

// (b) The returned x_{k+1} satisfies the collocation conditions in their state form, with f from
// the ABA (independent of the RNEA residual the solver drives to zero), also with springs,
// dampers and controls; both Jacobians give the same step.
TEST(HermiteSimpson, CollocationResidualVanishesAtSolution) {
  std::mt19937 rng(2);
  for (const Model& model : {models::pendulum(5), forced_pendulum(), test_models::branched_tree()}) {
    const int n = model.n(), m = model.n_controls();
    for (double dt : {0.002, 0.01, 0.05}) {
      HermiteSimpsonOptions opt;
      opt.tol = 1e-13;
      opt.reuse_jacobian = false;  // full Newton: quadratic convergence, a few iterations
      HermiteSimpson hs(model, dt, opt);
      const VecX q = uniform(rng, n, -1, 1), v = uniform(rng, n, -1, 1);
      const MatX u = m ? MatX(uniform(rng, 3 * m, -1, 1).reshaped(m, 3)) : MatX();
      VecX q1(n), v1(n);
      const SolveInfo info = hs.step(q, v, u, q1, v1);
      ASSERT_TRUE(info.converged()) << to_string(info.status) << " dt " << dt;
      EXPECT_LE(info.iterations, 6);
      // Simplified Newton (the default) reaches the same step.
      HermiteSimpsonOptions kept = opt;
      kept.reuse_jacobian = true;
      HermiteSimpson hs_kept(model, dt, kept);
      VecX q1k(n), v1k(n);
      ASSERT_TRUE(hs_kept.step(q, v, u, q1k, v1k).converged());
      EXPECT_LT((q1k - q1).cwiseAbs().maxCoeff(), 1e-12 * (1 + q1.cwiseAbs().maxCoeff()));
      EXPECT_LT((v1k - v1).cwiseAbs().maxCoeff(), 1e-10 * (1 + v1.cwiseAbs().maxCoeff()));
      const VecX r = hs.collocation_residual(q, v, q1, v1, u);
      const double x_norm = std::max(q.cwiseAbs().maxCoeff(), v.cwiseAbs().maxCoeff());
      EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-12 * (1 + x_norm)) << "n " << n << " dt " << dt;
      // The step moved: the residual is not trivially zero.
      EXPECT_GT((v1 - v).norm(), 1e-6);
      // The finite-difference Jacobian converges to the same point.
      opt.jacobian = HermiteSimpsonJacobian::FiniteDifference;
      HermiteSimpson fd(model, dt, opt);
      VecX q1f(n), v1f(n);
      ASSERT_TRUE(fd.step(q, v, u, q1f, v1f).converged());
      EXPECT_LT((q1f - q1).cwiseAbs().maxCoeff(), 1e-11);
      EXPECT_LT((v1f - v1).cwiseAbs().maxCoeff(), 1e-10);
    }
  }
}

// (a) Order of convergence of q(T) on the 5-link pendulum from a random state, against RK4 at
// a much smaller step whose own convergence is checked by halving it; also with springs,
// dampers and constant controls (the reference adds them independently of the solver).
TEST(HermiteSimpson, ConvergenceOrderOnPendulum) {
  for (const bool forced : {false, true}) {
    const Model model = forced ? forced_pendulum() : models::pendulum(5);
    const int n = model.n(), m = model.n_controls();
    std::mt19937 rng(3);
    const VecX q0 = uniform(rng, n, -1, 1), v0 = uniform(rng, n, -1, 1), u = uniform(rng, m, -2, 2);
    const double T = 1.0;
    // Reference: RK4 with 2^14 and 2^15 steps (h = 6.1e-5 and 3.1e-5).
    const VecX q_ref = rk4(model, q0, v0, T, 1 << 15, nullptr, u);
    const VecX q_ref2 = rk4(model, q0, v0, T, 1 << 14, nullptr, u);
    const double ref_err = (q_ref - q_ref2).cwiseAbs().maxCoeff();
    std::printf("%s: reference |RK4(2^14) - RK4(2^15)|_inf = %.3e\n", forced ? "springs, dampers, controls" : "pendulum(5)",
                ref_err);
    std::vector<double> err;
    const std::vector<int> steps = {10, 20, 40, 80, 160};
    for (int N : steps) {
      HermiteSimpsonOptions opt;
      opt.tol = 1e-13;
      HermiteSimpson hs(model, T / N, opt);
      const MatX U = m ? MatX(u.transpose().replicate(N, 3)) : MatX();  // u^{k,0} = u^{k,1/2} = u^{k,1} = u
      const HermiteSimpsonRollout out = hs.rollout(q0, v0, N, U);
      ASSERT_EQ(out.steps, N) << "dt " << T / N;
      err.push_back((out.q.row(N).transpose() - q_ref).cwiseAbs().maxCoeff());
    }
    for (size_t i = 0; i < err.size(); ++i) {
      const double order = i ? std::log2(err[i - 1] / err[i]) : 0.0;
      std::printf("  dt = %.5f  |q(T) - q_ref|_inf = %.3e  observed order %.2f\n", T / steps[i], err[i], order);
    }
    // The reference is far more accurate than the smallest HS error.
    EXPECT_LT(ref_err, 1e-3 * err.back());
    // The last three halvings: order >= 3 required; Lobatto IIIA (3 stages) is order 4 at the nodes.
    for (size_t i = 2; i < err.size(); ++i) EXPECT_GT(std::log2(err[i - 1] / err[i]), 3.5) << "dt " << T / steps[i];
  }
}

// (c) Invalid inputs.
TEST(HermiteSimpson, RejectsBadInput) {
  const Model model = models::pendulum(3);
  EXPECT_THROW(HermiteSimpson(model, 0.0), InputError);
  EXPECT_THROW(HermiteSimpson(model, -0.01), InputError);
  EXPECT_THROW(HermiteSimpson(model, std::nan("")), InputError);
  EXPECT_THROW(HermiteSimpson(model, std::numeric_limits<double>::infinity()), InputError);
  HermiteSimpsonOptions opt;
  opt.tol = 0;
  EXPECT_THROW(HermiteSimpson(model, 0.01, opt), InputError);
  opt = HermiteSimpsonOptions();
  opt.max_iterations = 0;
  EXPECT_THROW(HermiteSimpson(model, 0.01, opt), InputError);
  EXPECT_THROW(HermiteSimpson(Model(), 0.01), ModelError);
  Model drag = models::pendulum(3);
  drag.add_wrench(std::make_shared<BodyDrag>(1, 0.1, 0.1));
  EXPECT_THROW(HermiteSimpson(drag, 0.01), ModelError);
  HermiteSimpson hs(model, 0.01);
  VecX q1(3), v1(3);
  EXPECT_THROW(hs.step(VecX::Zero(2), VecX::Zero(3), MatX(), q1, v1), InputError);
  EXPECT_THROW(hs.step(VecX::Constant(3, std::nan("")), VecX::Zero(3), MatX(), q1, v1), InputError);
  EXPECT_THROW(hs.rollout(VecX::Zero(3), VecX::Zero(3), -1), InputError);
  const Model forced = forced_pendulum();
  HermiteSimpson hf(forced, 0.01);
  EXPECT_THROW(hf.step(VecX::Zero(5), VecX::Zero(5), MatX::Zero(2, 2), q1, v1), InputError);
  EXPECT_THROW(hf.rollout(VecX::Zero(5), VecX::Zero(5), 4, MatX::Zero(4, 5)), InputError);
}

// (d) A large step either converges (to a point satisfying the collocation conditions) or
// reports a failure; a failed step is never reported as converged and stops the rollout.
TEST(HermiteSimpson, LargeStepConvergesOrFailsExplicitly) {
  const Model model = models::pendulum(5);
  const int n = model.n();
  std::mt19937 rng(4);
  int converged = 0, failed = 0;
  for (double dt : {0.1, 0.3, 1.0, 3.0}) {
    for (int trial = 0; trial < 3; ++trial) {
      HermiteSimpsonOptions opt;
      opt.max_iterations = 15;
      HermiteSimpson hs(model, dt, opt);
      const VecX q = uniform(rng, n, -2, 2), v = uniform(rng, n, -5, 5);
      VecX q1(n), v1(n);
      const SolveInfo info = hs.step(q, v, MatX(), q1, v1);
      if (info.converged()) {
        ++converged;
        EXPECT_TRUE(std::isfinite(info.residual));
        EXPECT_TRUE(q1.allFinite() && v1.allFinite());
        const VecX r = hs.collocation_residual(q, v, q1, v1);
        EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-6 * (1 + std::max(q1.cwiseAbs().maxCoeff(), v1.cwiseAbs().maxCoeff())));
      } else {
        ++failed;
        EXPECT_NE(info.status, SolveStatus::Converged);
      }
      std::printf("dt = %.1f: %s after %d iterations, residual %.2e\n", dt, to_string(info.status), info.iterations,
                  info.residual);
    }
  }
  std::printf("large steps: %d converged, %d failed\n", converged, failed);
  // max_iterations = 1 cannot reach 1e-10 from a rest guess at dt = 1: an explicit failure.
  HermiteSimpsonOptions opt;
  opt.max_iterations = 1;
  HermiteSimpson hs(model, 1.0, opt);
  const HermiteSimpsonRollout out = hs.rollout(VecX::Constant(n, 0.8), VecX::Zero(n), 5);
  EXPECT_EQ(out.steps, 0);
  ASSERT_EQ(out.status.size(), 1u);
  EXPECT_EQ(out.status[0], SolveStatus::MaxIterations);
}

// Rollouts with controls: the state form of the collocation conditions holds at every step.
TEST(HermiteSimpson, RolloutWithControls) {
  const Model model = forced_pendulum();
  const int n = model.n(), m = model.n_controls(), N = 20;
  const double dt = 0.01;
  MatX u(N, 3 * m);
  for (int k = 0; k < N; ++k)
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < m; ++j) u(k, c * m + j) = std::sin(3 * (k + 0.5 * c) * dt + j);  // u(t) sampled at t_k, t_k + h/2, t_{k+1}
  HermiteSimpson hs(model, dt);
  const VecX q0 = VecX::Constant(n, 0.3), v0 = VecX::Zero(n);
  const HermiteSimpsonRollout out = hs.rollout(q0, v0, N, u);
  ASSERT_EQ(out.steps, N);
  for (int k = 0; k < N; ++k) {
    EXPECT_EQ(out.status[k], SolveStatus::Converged);
    EXPECT_LE(out.iterations[k], 3);
    const MatX uk = u.row(k).reshaped(m, 3);
    const VecX r = hs.collocation_residual(out.q.row(k).transpose(), out.v.row(k).transpose(),
                                           out.q.row(k + 1).transpose(), out.v.row(k + 1).transpose(), uk);
    EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-9);
  }
}

// Sec. 5.3 / Fig. 4 setting: 12-link pendulum, q0 ~ U[-pi/12, pi/12], v0 = 0, T = 10 s. Prints the
// time per step (best of 3 runs of each rollout), Newton iterations per step and the error
// against a fine RK4 reference, (1/T) ∫ ||q - q_ref|| dt and max |q(T) - q_ref(T)|, for
// Hermite-Simpson (analytic and finite-difference Jacobians) and hovi's Simpson VI (s = 2), at
// the default tol 1e-10 and at 1e-13. Takes a few minutes.
// Run with --gtest_also_run_disabled_tests --gtest_filter='*HermiteSimpsonTiming*'.
TEST(HermiteSimpson, DISABLED_HermiteSimpsonTiming) {
  const Model model = models::pendulum(12);
  const int n = model.n();
  const double T = 10.0;
  const int trials = 5;
  using clock = std::chrono::steady_clock;
  struct Method {
    const char* name;
    bool hs;
    HermiteSimpsonJacobian jacobian;
    double tol;
    int reps;
  };
  const std::vector<Method> methods = {
      {"HS analytic J", true, HermiteSimpsonJacobian::Analytic, 1e-10, 3},
      {"HS finite-diff J", true, HermiteSimpsonJacobian::FiniteDifference, 1e-10, 1},
      {"Simpson VI", false, HermiteSimpsonJacobian::Analytic, 1e-10, 3},
      {"HS analytic J", true, HermiteSimpsonJacobian::Analytic, 1e-13, 3},
      {"Simpson VI", false, HermiteSimpsonJacobian::Analytic, 1e-13, 3},
  };
  std::printf("%-18s %7s %6s %9s %9s %8s %11s %11s\n", "method", "tol", "dt", "us/step", "us/iter", "iter/st",
              "mean|dq|", "max|dq(T)|");
  for (double dt : {0.001, 0.005, 0.01, 0.02}) {
    const int N = static_cast<int>(std::lround(T / dt));
    std::vector<double> seconds(methods.size(), 0), mean_err(methods.size(), 0), end_err(methods.size(), 0);
    std::vector<long> iters(methods.size(), 0);
    std::mt19937 rng(100);
    for (int trial = 0; trial < trials; ++trial) {
      const VecX q0 = uniform(rng, n, -M_PI / 12, M_PI / 12), v0 = VecX::Zero(n);
      // Reference at the nodes: RK4 with h = dt/64 (dt/32 at dt = 0.001).
      MatX q_ref(N + 1, n);
      {
        const int sub = dt < 0.004 ? 32 : 64;
        VecX q = q0, v = v0, v_next;
        q_ref.row(0) = q.transpose();
        for (int k = 0; k < N; ++k) {
          q = rk4(model, q, v, dt, sub, &v_next);
          v = v_next;
          q_ref.row(k + 1) = q.transpose();
        }
      }
      for (size_t mi = 0; mi < methods.size(); ++mi) {
        const Method& me = methods[mi];
        MatX q_out;
        double best = 1e300;
        for (int rep = 0; rep < me.reps; ++rep) {
          if (me.hs) {
            HermiteSimpsonOptions opt;
            opt.jacobian = me.jacobian;
            opt.tol = me.tol;
            HermiteSimpson hs(model, dt, opt);
            const auto t0 = clock::now();
            const HermiteSimpsonRollout out = hs.rollout(q0, v0, N);
            best = std::min(best, std::chrono::duration<double>(clock::now() - t0).count());
            ASSERT_EQ(out.steps, N);
            if (rep == 0) iters[mi] += out.iterations.sum();
            q_out = out.q;
          } else {
            SolverOptions opt;
            opt.tol = me.tol;
            GalerkinIntegrator vi(model, 2, dt, opt);
            const VecX p0 = vi.momentum(q0, v0);
            const auto t0 = clock::now();
            const Rollout out = vi.rollout(q0, p0, N, MatX());
            best = std::min(best, std::chrono::duration<double>(clock::now() - t0).count());
            ASSERT_EQ(out.steps, N);
            if (rep == 0) iters[mi] += out.iterations.sum();
            q_out = out.q;
          }
        }
        seconds[mi] += best;
        double e = 0;  // (1/T) ∫ ||q - q_ref|| dt, trapezoidal rule on the nodes
        for (int k = 0; k <= N; ++k) e += (k == 0 || k == N ? 0.5 : 1.0) * (q_out.row(k) - q_ref.row(k)).norm();
        mean_err[mi] += e * dt / T / trials;
        end_err[mi] = std::max(end_err[mi], (q_out.row(N) - q_ref.row(N)).cwiseAbs().maxCoeff());
      }
    }
    for (size_t mi = 0; mi < methods.size(); ++mi) {
      const long steps = static_cast<long>(N) * trials;
      std::printf("%-18s %7.0e %6.3f %9.2f %9.2f %8.2f %11.3e %11.3e\n", methods[mi].name, methods[mi].tol, dt,
                  1e6 * seconds[mi] / steps, 1e6 * seconds[mi] / iters[mi], double(iters[mi]) / steps, mean_err[mi],
                  end_err[mi]);
    }
  }
}
