// The quasi-Newton baseline of Lee, Liu, Park, Srinivasa (WAFR 2016) on the trapezoidal DEL
// equations: it converges to the same step as hovi's exact Newton method; every step is the
// dense solve dq = -J̃^{-1} r with J̃ = -(1/dt) M(q^k) built independently (M = Σ J_i^T M̄_i J_i);
// J̃ is the DEL Jacobian to first order in dt; failures are reported, never marked converged.
// DISABLED_QuasiNewton.Fig2Measurement prints the iterations / success table of Fan et al. Fig. 2.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "test_models.hpp"
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/baselines/quasi_newton.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

constexpr double kPi = 3.14159265358979323846;

// M(q) = Σ_i J_i^T M̄_i J_i with the spatial Jacobian J_i = [S̄_j for j in anc(i) ∪ {i}]: dense,
// from the kinematics only (no composite or articulated inertias).
MatX dense_mass_matrix(const Model& model, const VecX& q) {
  Data data(model);
  forward_kinematics(model, data, q);
  const int n = model.n();
  MatX M = MatX::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> J = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, n);
    for (int j = i; j >= 0; j = model.parent[j]) J.col(j) = data.Sbar[j];
    M += J.transpose() * data.Mbar[i].matrix() * J;
  }
  return M;
}

// The matrix the quasi-Newton step claims to invert: J̃ = -(1/dt) M(q^k) ≈ ∂r/∂q^{k+1}.
MatX approximate_jacobian(const Model& model, const VecX& qk, double dt) { return -dense_mass_matrix(model, qk) / dt; }


struct State {
  VecX q, qdot, p;
};

// Fan et al. Sec. 5.1: q^0, q̇^0 uniform in [-amp, amp], p^0 = M(q^0) q̇^0.
State random_state(const Model& model, std::mt19937& rng, double amp = kPi / 2) {
  std::uniform_real_distribution<double> U(-amp, amp);
  const int n = model.n();
  State st{VecX(n), VecX(n), VecX(n)};
  for (int i = 0; i < n; ++i) st.q[i] = U(rng);
  for (int i = 0; i < n; ++i) st.qdot[i] = U(rng);
  Data data(model);
  st.p = mass_matrix(model, data, st.q) * st.qdot;
  return st;
}

MatX guess(const State& st, double dt) {  // q^{k+1} = q^k + dt q̇^k
  MatX qc(st.q.size(), 2);
  qc.col(0) = st.q;
  qc.col(1) = st.q + dt * st.qdot;
  return qc;
}

double inf_norm(const VecX& x) { return x.cwiseAbs().maxCoeff(); }

}  // namespace

// Converges to hovi's exact Newton solution (same tolerance, same stopping rule) from the states of
// Fan et al. Fig. 2 (q, q̇ uniform in [-π/2, π/2]). Agreement: |Δq^{k+1}|_inf < 1e-9 and
// |Δp^{k+1}|_inf < 1e-9 (1 + |p^{k+1}|_inf). p^{k+1} is compared relatively because it moves with
// the residual (∂p^{k+1}/∂q^{k+1} ≈ -∂r/∂q^{k+1} ≈ M/dt, up to ~3e6 for n = 32 at dt = 0.001), so its
// round-off floor is ~eps |q| |M| / dt ≈ 1e-9 absolute while |p|_inf reaches ~2000. Both solvers run
// at tol = 1e-12 (hovi's default 1e-10 (1 + |p|_inf) is up to 2e-7 here; the quasi-Newton stops
// just under its target, Newton far below). At dt = 0.01 the quasi-Newton iteration diverges from
// some of these states (the spectral radius of I - J̃^{-1} J exceeds 1 there): those states are
// reported, and the test requires agreement on every state where both converge, and convergence
// on all states at dt = 0.001 and on most at dt = 0.01.
TEST(QuasiNewton, MatchesNewtonOnPendulum) {
  std::mt19937 rng(7);
  for (int n : {4, 32}) {
    const Model model = models::pendulum(n);
    const Quadrature quad(1);
    const MatX u(0, 2);
    for (double dt : {0.001, 0.01}) {
      QuasiNewtonSolver qn(model, dt, QuasiNewtonOptions{1e-12, 300});
      NewtonSolver newton(model, quad);
      SolverOptions nopt;
      nopt.tol = qn.options.tol;
      const int trials = 6;
      int compared = 0;
      for (int trial = 0; trial < trials; ++trial) {
        const State st = random_state(model, rng);
        MatX qc_qn = guess(st, dt), qc_n = guess(st, dt);
        VecX p_qn(n), p_n(n);
        const SolveInfo iq = qn.solve(st.p, u, qc_qn, p_qn);
        const SolveInfo in = newton.solve(model, quad, nopt, st.p, u, dt, qc_n, p_n);
        SCOPED_TRACE("n = " + std::to_string(n) + ", dt = " + std::to_string(dt) + ", trial " + std::to_string(trial));
        EXPECT_EQ(qc_qn.col(0), st.q);  // q^k untouched
        if (!in.converged() || !iq.converged()) {
          std::printf("  [n %d, dt %g, trial %d] not compared: Newton %s (%d it, |r| %.2e), quasi-Newton %s (%d it, |r| %.2e)\n",
                      n, dt, trial, to_string(in.status), in.iterations, in.residual, to_string(iq.status),
                      iq.iterations, iq.residual);
          continue;
        }
        ++compared;
        // Below the target, or at the round-off floor where both solvers' second rule (a step below
        // 1e-14 (1 + |q|_inf)) stops them: |r| ~ |J̃| 1e-14 (1 + |q|_inf).
        const MatX Jt = approximate_jacobian(model, st.q, dt);
        const double floor = 1e-14 * (1 + inf_norm(qc_qn.col(1))) * Jt.cwiseAbs().rowwise().sum().maxCoeff();
        EXPECT_LE(iq.residual, std::max(qn.options.tol * (1 + inf_norm(st.p)), floor));
        EXPECT_GE(iq.iterations, in.iterations);  // linear vs quadratic convergence
        EXPECT_LT(inf_norm(qc_qn.col(1) - qc_n.col(1)), 1e-9);
        EXPECT_LT(inf_norm(p_qn - p_n), 1e-9 * (1 + inf_norm(p_n)));
      }
      SCOPED_TRACE("n = " + std::to_string(n) + ", dt = " + std::to_string(dt));
      if (dt <= 0.001) EXPECT_EQ(compared, trials);
      else EXPECT_GE(compared, n == 4 ? trials : trials / 2);
    }
  }
}

// direction(r) = -J̃^{-1} r, with J̃ = -(1/dt) M(q^k) built densely and solved by LU.
TEST(QuasiNewton, DirectionIsDenseSolveOfMassMatrix) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-kPi, kPi);
  for (const Model& model : {models::pendulum(4), models::pendulum(32), test_models::branched_tree()}) {
    const int n = model.n();
    const double dt = 0.02;
    QuasiNewtonSolver qn(model, dt);
    Data data(model);
    for (int trial = 0; trial < 3; ++trial) {
      VecX qk(n), r(n);
      for (int i = 0; i < n; ++i) qk[i] = U(rng);
      for (int i = 0; i < n; ++i) r[i] = U(rng);
      const MatX Jt = approximate_jacobian(model, qk, dt);
      // The dense M agrees with hovi's CRBA, a third computation.
      EXPECT_LT((-dt * Jt - mass_matrix(model, data, qk)).norm(), 1e-12 * (1 + Jt.norm() * dt));
      const VecX dq_dense = -Jt.fullPivLu().solve(r);
      ASSERT_TRUE(qn.factor(qk));
      VecX dq(n);
      qn.direction(r, dq);
      EXPECT_LT((dq - dq_dense).norm(), 1e-9 * dq_dense.norm()) << "n = " << n;
      EXPECT_LT((Jt * dq + r).norm(), 1e-9 * r.norm());
    }
  }
}

// Inside solve(), every step is the dense step at the current iterate, with M fixed at q^k.
TEST(QuasiNewton, EachIterationIsTheDenseStep) {
  std::mt19937 rng(3);
  const Model model = models::pendulum(32);
  const Quadrature quad(1);
  const MatX u(0, 2);
  const double dt = 0.01;
  const State st = random_state(model, rng);
  QuasiNewtonSolver qn(model, dt);
  qn.options.max_iterations = 1;  // one step per call, continuing from the last iterate
  const MatX Jt = approximate_jacobian(model, st.q, dt);
  const Eigen::FullPivLU<MatX> lu(Jt);
  DelWorkspace ws(model, quad);
  MatX qc = guess(st, dt), r(model.n(), 1);
  VecX p_next(model.n()), p_ref(model.n());
  double first = 0, last = 0;
  for (int it = 0; it < 5; ++it) {
    del_residual(model, quad, ws, qc, st.p, u, dt, r, p_ref);
    const VecX dq_dense = -lu.solve(VecX(r.col(0)));
    const VecX before = qc.col(1);
    const SolveInfo info = qn.solve(st.p, u, qc, p_next);
    ASSERT_EQ(info.iterations, 1);
    ASSERT_EQ(info.status, SolveStatus::MaxIterations);
    EXPECT_LT((VecX(qc.col(1)) - before - dq_dense).norm(), 1e-10 * (1 + dq_dense.norm())) << "iteration " << it;
    if (it == 0) first = r.cwiseAbs().maxCoeff();
    last = info.residual;
  }
  EXPECT_LT(last, 1e-2 * first);  // and it contracts
}

// J̃ = -(1/dt) M(q^k) is the DEL Jacobian ∂r/∂q^{k+1} up to O(dt) relative error: this is what
// makes the quasi-Newton step a descent step, and why it degrades at large dt (Fan et al. Fig. 2).
TEST(QuasiNewton, ApproximationIsJacobianToFirstOrder) {
  std::mt19937 rng(5);
  const Model model = models::pendulum(4);
  const Quadrature quad(1);
  const MatX u(0, 2);
  const int n = model.n();
  const State st = random_state(model, rng, 0.5);
  DelWorkspace ws(model, quad);
  double err[2];
  int k = 0;
  for (double dt : {0.01, 0.001}) {
    MatX qc = guess(st, dt), r(n, 1), rp(n, 1), rm(n, 1);
    VecX pn(n);
    MatX J(n, n);
    for (int j = 0; j < n; ++j) {  // central differences in q^{k+1}
      const double h = 1e-6;
      MatX qp = qc, qm = qc;
      qp(j, 1) += h;
      qm(j, 1) -= h;
      del_residual(model, quad, ws, qp, st.p, u, dt, rp, pn);
      del_residual(model, quad, ws, qm, st.p, u, dt, rm, pn);
      J.col(j) = (rp - rm).col(0) / (2 * h);
    }
    const MatX Jt = approximate_jacobian(model, st.q, dt);
    err[k++] = (J - Jt).norm() / J.norm();
  }
  EXPECT_LT(err[0], 0.2);
  EXPECT_LT(err[1], 0.02);
  EXPECT_GT(err[0] / err[1], 5);  // first order in dt
}

// A run that fails reports a non-converged status; NaN is never reported as converged.
TEST(QuasiNewton, FailureIsReportedNotConverged) {
  const Model model = models::pendulum(32);
  const MatX u(0, 2);
  std::mt19937 rng(13);
  // A non-finite guess: NonFinite, not Converged.
  {
    QuasiNewtonSolver qn(model, 0.01);
    const State st = random_state(model, rng);
    MatX qc = guess(st, 0.01);
    qc(5, 1) = std::numeric_limits<double>::quiet_NaN();
    VecX p_next(model.n());
    const SolveInfo info = qn.solve(st.p, u, qc, p_next);
    EXPECT_EQ(info.status, SolveStatus::NonFinite);
    EXPECT_FALSE(info.converged());
  }
  // No iterations allowed from a guess that is not a solution: MaxIterations.
  {
    QuasiNewtonSolver qn(model, 0.01, QuasiNewtonOptions{1e-10, 0});
    const State st = random_state(model, rng);
    MatX qc = guess(st, 0.01);
    VecX p_next(model.n());
    const SolveInfo info = qn.solve(st.p, u, qc, p_next);
    EXPECT_EQ(info.status, SolveStatus::MaxIterations);
    EXPECT_EQ(info.iterations, 0);
  }
  // Large steps: the fixed-matrix iteration fails on some states. Whatever the outcome, a
  // converged report has a finite residual below the target and finite outputs.
  QuasiNewtonSolver qn(model, 0.06);
  int failures = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const State st = random_state(model, rng);
    MatX qc = guess(st, 0.06);
    VecX p_next(model.n());
    const SolveInfo info = qn.solve(st.p, u, qc, p_next);
    if (info.converged()) {
      EXPECT_TRUE(std::isfinite(info.residual));
      EXPECT_LE(info.residual, qn.options.tol * (1 + inf_norm(st.p)));
      EXPECT_TRUE(qc.allFinite());
      EXPECT_TRUE(p_next.allFinite());
    } else {
      ++failures;
      EXPECT_TRUE(info.status == SolveStatus::MaxIterations || info.status == SolveStatus::NonFinite)
          << to_string(info.status);
      EXPECT_TRUE(info.status == SolveStatus::NonFinite || std::isfinite(info.residual));
    }
  }
  EXPECT_GT(failures, 0);
}

// Fan et al. Fig. 2 protocol (32-link pendulum, one trapezoidal step from random states) on 50
// states per dt: iterations, success rate and time per solve (over successful solves, as in the
// paper), quasi-Newton vs hovi's Newton, both from the same initial guess.
// Run with --gtest_also_run_disabled_tests --gtest_filter='*QuasiNewton*Fig2*'.
TEST(DISABLED_QuasiNewton, Fig2Measurement) {
  const int n = 32, trials = 50;
  const Model model = models::pendulum(n);
  const Quadrature quad(1);
  const MatX u(0, 2);
  Data data(model);
  std::printf("32-link pendulum, trapezoidal VI, %d random states per dt, tol 1e-10 (1 + |p|_inf)\n", trials);
  for (int guess_kind = 0; guess_kind < 2; ++guess_kind) {
    std::printf("\ninitial guess: %s\n", guess_kind == 0 ? "q^k + dt qdot^k"
                                                         : "q^k + dt qdot^k + dt^2 qddot^k (Lee et al.'s IG)");
    std::printf("%6s | %-32s | %-32s\n", "dt", "quasi-Newton (Lee et al. 2016)", "Newton (hovi, exact O(n))");
    std::printf("%6s | %7s %6s %6s %9s | %7s %6s %6s %9s\n", "", "success", "mean", "max", "us/solve", "success",
                "mean", "max", "us/solve");
    for (double dt : {0.001, 0.01, 0.03, 0.06}) {
      std::mt19937 rng(2018);
      QuasiNewtonSolver qn(model, dt);
      NewtonSolver newton(model, quad);
      SolverOptions nopt;
      nopt.tol = qn.options.tol;
      int ok[2] = {0, 0}, maxit[2] = {0, 0};
      double sum_it[2] = {0, 0}, sum_t[2] = {0, 0};
      for (int t = 0; t < trials; ++t) {
        const State st = random_state(model, rng);
        MatX qc0 = guess(st, dt);
        if (guess_kind == 1) {
          const VecX qdd = forward_dynamics(model, data, st.q, st.qdot, VecX::Zero(n));
          qc0.col(1) += dt * dt * qdd;
        }
        for (int solver = 0; solver < 2; ++solver) {
          SolveInfo info;
          double us = std::numeric_limits<double>::infinity();
          for (int rep = 0; rep < 5; ++rep) {  // time per solve: the minimum of 5 identical solves
            MatX qc = qc0;
            VecX p_next(n);
            const auto t0 = std::chrono::steady_clock::now();
            info = solver == 0 ? qn.solve(st.p, u, qc, p_next)
                               : newton.solve(model, quad, nopt, st.p, u, dt, qc, p_next);
            us = std::min(us, std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
          }
          if (!info.converged()) continue;
          ++ok[solver];
          sum_it[solver] += info.iterations;
          sum_t[solver] += us;
          maxit[solver] = std::max(maxit[solver], info.iterations);
        }
      }
      auto cell = [&](int s) {
        if (ok[s] == 0) return std::printf(" %6.0f%% %6s %6s %9s |", 0.0, "-", "-", "-");
        return std::printf(" %6.0f%% %6.1f %6d %9.1f |", 100.0 * ok[s] / trials, sum_it[s] / ok[s], maxit[s],
                           sum_t[s] / ok[s]);
      };
      std::printf("%6.3f |", dt);
      cell(0);
      cell(1);
      std::printf("\n");
    }
  }
}
