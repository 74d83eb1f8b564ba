// The automatic-differentiation baseline (Sec. 5.2) against hovi's recursive algorithms: the DEL
// residual (Alg. 1), the Newton direction (A.1/A.2), D^2 L_d (Sec. 4) and a whole Newton solve,
// on a 5-link pendulum and a branched tree with a prismatic joint, gravity, joint springs,
// dampers and actuators, s = 1..3. The two sides share only the Model's constant data.
// DISABLED_AutodiffDel.Timing prints per-call times for the Simpson rule (s = 2) on pendulums.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <random>

#include "test_models.hpp"
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/baselines/autodiff_lagrangian.hpp"
#include "hovi/errors.hpp"
#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {


// Gravity is on by default; springs with a rest position, dampers and two actuators.
void add_forces(Model& m) {
  const int n = m.n();
  for (int i = 0; i < n; ++i) {
    m.add_spring(i, 2.0 + 0.5 * i, 0.1 * i - 0.2);
    if (i % 2 == 0) m.add_damper(i, 0.3 + 0.1 * i);
  }
  m.add_actuator(0, 1.5);
  m.add_actuator(n - 1, 0.7);
}

Model forced_pendulum() {
  Model m = models::pendulum(5);
  add_forces(m);
  return m;
}
Model forced_tree() {
  Model m = test_models::branched_tree();
  add_forces(m);
  return m;
}

double rel(const MatX& a, const MatX& ref) { return (a - ref).norm() / ref.norm(); }

// Control points of a step from q with velocity qd (plus a perturbation), controls, momentum.
struct Sample {
  MatX qc, u;
  VecX p;
};
Sample sample(const Model& model, const Quadrature& quad, double dt, std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1, 1);
  const int n = model.n(), s = quad.s;
  Sample x;
  VecX q(n), qd(n);
  for (int i = 0; i < n; ++i) q[i] = U(rng), qd[i] = 2 * U(rng);
  x.qc.resize(n, s + 1);
  for (int a = 0; a <= s; ++a)
    for (int i = 0; i < n; ++i) x.qc(i, a) = q[i] + quad.c[a] * dt * qd[i] + (a > 0 ? 0.01 * U(rng) : 0.0);
  x.u.resize(model.n_controls(), s + 1);
  for (int k = 0; k < x.u.size(); ++k) x.u.data()[k] = U(rng);
  Data data(model);
  x.p = mass_matrix(model, data, q) * qd;
  for (int i = 0; i < n; ++i) x.p[i] += 0.1 * U(rng);
  return x;
}

constexpr double kDt = 0.02;

// A step under the Simpson rule (s = 2) of length dt, sampled from seed.
struct SimpsonStep {
  Quadrature quad{2};
  double dt;
  Sample x;
  SimpsonStep(const Model& model, double dt_, unsigned seed) : dt(dt_) {
    std::mt19937 rng(seed);
    x = sample(model, quad, dt, rng);
  }
};

// check(quad, ad, rng) for s = 1, 2, 3 at dt = kDt, each under a trace of its s.
template <class Check>
void for_orders(const Model& model, unsigned seed, Check check) {
  std::mt19937 rng(seed);
  for (int s = 1; s <= 3; ++s) {
    SCOPED_TRACE("s = " + std::to_string(s));
    const Quadrature quad(s);
    AutodiffDel ad(model, quad, kDt);
    check(quad, ad, rng);
  }
}

void check_against_hovi(const Model& model) {
  const int n = model.n();
  const double dt = kDt;
  for_orders(model, 7, [&](const Quadrature& quad, AutodiffDel& ad, std::mt19937& rng) {
    const int s = quad.s;
    DelWorkspace del(model, quad);
    NewtonWorkspace nws(model, quad);
    DelJacobianWorkspace jws(model, quad);
    Data data(model);
    for (int trial = 0; trial < 3; ++trial) {
      const Sample x = sample(model, quad, dt, rng);

      // L_d itself against hovi's energies (K, and V with gravity and springs)
      const MatX qd = x.qc * quad.b.transpose() / dt;
      double Ld = 0;
      for (int a = 0; a <= s; ++a)
        Ld += quad.w[a] * dt *
              (kinetic_energy(model, data, x.qc.col(a), qd.col(a)) - potential_energy(model, data, x.qc.col(a)));
      EXPECT_NEAR(ad.lagrangian(x.qc), Ld, 1e-12 * (1 + std::abs(Ld)));

      // DEL residual (Alg. 1)
      MatX r(n, s), r_ad;
      VecX pn(n), pn_ad;
      del_residual(model, quad, del, x.qc, x.p, x.u, dt, r, pn);
      ad.residual(x.qc, x.p, x.u, r_ad, pn_ad);
      EXPECT_LT(rel(r_ad, r), 1e-10);
      EXPECT_LT(rel(pn_ad, pn), 1e-10);

      // Newton direction (A.1/A.2) on the workspace of the del_residual call above
      MatX dq(n, s), dq_ad;
      ASSERT_TRUE(newton_direction(model, quad, del, nws, r, dq));
      ad.newton_direction(x.qc, x.p, x.u, dq_ad);
      EXPECT_LT(rel(dq_ad, dq), 1e-8);

      // D^2 L_d (Sec. 4, Algorithms 2 and 3). hovi's L_d has V = V_g and counts the springs among
      // the joint forces Q; the baseline's V includes the springs' potential, whose Hessian is
      // the block diagonal -w^b dt k_i.
      const int N = (s + 1) * n;
      MatX H(N, N), H_ad;
      dlagrangian_hessian(model, quad, jws, x.qc, dt, H);
      for (int b = 0; b <= s; ++b)
        for (int i = 0; i < n; ++i) H(b * n + i, b * n + i) -= quad.w[b] * dt * model.joint_forces.stiffness[i];
      ad.d2Ld(x.qc, H_ad);
      EXPECT_LT(rel(H_ad, H), 1e-9);
      EXPECT_LT((H_ad - H_ad.transpose()).norm(), 1e-12 * H.norm());

      // The DEL Jacobian: rows r^{0..s-1}, columns q^{1..s} of hovi's Jq
      MatX Jq(N, N), J_ad;
      del_jacobian(model, quad, jws, x.qc, x.u, dt, Jq, nullptr);
      ad.jacobian(x.qc, x.u, J_ad);
      EXPECT_LT(rel(J_ad, Jq.topRightCorner(s * n, s * n)), 1e-9);
    }
  });
}

// A whole step: full Newton iterations with the AD direction and residual converge to the step
// hovi's NewtonSolver finds.
void check_newton_solve(const Model& model) {
  SolverOptions opt;
  opt.tol = 1e-13;
  for_orders(model, 11, [&](const Quadrature& quad, AutodiffDel& ad, std::mt19937& rng) {
    const int s = quad.s, n = model.n();
    const double dt = kDt;
    NewtonSolver solver(model, quad);
    for (int trial = 0; trial < 2; ++trial) {
      Sample x = sample(model, quad, dt, rng);
      for (int a = 1; a <= s; ++a) x.qc.col(a) = x.qc.col(0);  // initial guess: at rest at q^k
      MatX q_hovi = x.qc, q_ad = x.qc;
      VecX pn_hovi(n), pn_ad(n);
      const SolveInfo info = solver.solve(model, quad, opt, x.p, x.u, dt, q_hovi, pn_hovi);
      ASSERT_TRUE(info.converged()) << to_string(info.status);

      MatX r, dq;
      int it = 0;
      for (; it < 30; ++it) {
        ad.residual(q_ad, x.p, x.u, r, pn_ad);
        if (r.cwiseAbs().maxCoeff() <= 1e-13 * (1 + x.p.cwiseAbs().maxCoeff())) break;
        ad.newton_direction(q_ad, x.p, x.u, dq);
        q_ad.rightCols(s) += dq;
        if (dq.cwiseAbs().maxCoeff() <= 1e-15 * (1 + q_ad.cwiseAbs().maxCoeff())) {
          ad.residual(q_ad, x.p, x.u, r, pn_ad);
          break;
        }
      }
      EXPECT_LT(it, 30);
      EXPECT_LT((q_ad - q_hovi).cwiseAbs().maxCoeff(), 1e-10 * (1 + q_hovi.cwiseAbs().maxCoeff()));
      EXPECT_LT((pn_ad - pn_hovi).cwiseAbs().maxCoeff(), 1e-10 * (1 + pn_hovi.cwiseAbs().maxCoeff()));
    }
  });
}

}  // namespace

TEST(AutodiffDel, PendulumMatchesRecursiveAlgorithms) { check_against_hovi(forced_pendulum()); }
TEST(AutodiffDel, BranchedTreeMatchesRecursiveAlgorithms) { check_against_hovi(forced_tree()); }
TEST(AutodiffDel, PendulumNewtonSolveMatchesNewtonSolver) { check_newton_solve(forced_pendulum()); }
TEST(AutodiffDel, BranchedTreeNewtonSolveMatchesNewtonSolver) { check_newton_solve(forced_tree()); }

// Without springs the two D^2 L_d are the same object.
TEST(AutodiffDel, UnforcedHessianMatchesDirectly) {
  for (const Model& model : {models::pendulum(4), test_models::branched_tree()}) {
    const SimpsonStep st(model, 0.05, 5);
    AutodiffDel ad(model, st.quad, st.dt);
    DelJacobianWorkspace jws(model, st.quad);
    const int N = 3 * model.n();
    MatX H(N, N), H_ad;
    dlagrangian_hessian(model, st.quad, jws, st.x.qc, st.dt, H);
    ad.d2Ld(st.x.qc, H_ad);
    EXPECT_LT(rel(H_ad, H), 1e-9);
  }
}

// Body frames away from the centre of mass (first moment h = m c != 0): K with the full spatial
// inertia, V = -sum g^T (m p_i + R_i h_i). hovi's algorithms take gravity at the frame origin
// (docs/paper.md C-3), so the derivatives are compared without gravity and the value with it.
TEST(AutodiffDel, NonComFramesMatch) {
  Model model = forced_tree();
  for (int i = 0; i < model.n(); ++i) {
    const SpatialInertia& Mc = model.M[i];
    const Vec3 c(0.1, -0.05 * i, 0.02 * i + 0.03);
    model.M[i] = SpatialInertia(Mc.m, Mc.m * c, Mc.I - Mc.m * hat(c) * hat(c));  // M about a point -c from the COM
  }
  const SimpsonStep st(model, 0.02, 13);
  const Quadrature& quad = st.quad;
  const double dt = st.dt;
  const Sample& x = st.x;
  const int n = model.n();
  {  // L_d with gravity
    AutodiffDel ad(model, quad, dt);
    Data data(model);
    const MatX qd = x.qc * quad.b.transpose() / dt;
    double Ld = 0;
    for (int a = 0; a <= 2; ++a) {
      const double K = kinetic_energy(model, data, x.qc.col(a), qd.col(a));  // also fills data.g
      double Vg = 0, Vg_origin = 0;
      for (int i = 0; i < n; ++i) {
        Vg -= model.gravity.dot(model.M[i].m * data.g[i].p + data.g[i].R * model.M[i].h);
        Vg_origin -= model.M[i].m * model.gravity.dot(data.g[i].p);
      }
      // hovi's potential_energy = V_g with the mass at the frame origin + the springs' V_s
      const double V = potential_energy(model, data, x.qc.col(a)) - Vg_origin + Vg;
      Ld += quad.w[a] * dt * (K - V);
    }
    EXPECT_NEAR(ad.lagrangian(x.qc), Ld, 1e-12 * (1 + std::abs(Ld)));
  }
  model.gravity.setZero();
  AutodiffDel ad(model, quad, dt);
  DelWorkspace del(model, quad);
  NewtonWorkspace nws(model, quad);
  MatX r(n, 2), r_ad, dq(n, 2), dq_ad;
  VecX pn(n), pn_ad;
  del_residual(model, quad, del, x.qc, x.p, x.u, dt, r, pn);
  ad.residual(x.qc, x.p, x.u, r_ad, pn_ad);
  EXPECT_LT(rel(r_ad, r), 1e-10);
  EXPECT_LT(rel(pn_ad, pn), 1e-10);
  ASSERT_TRUE(newton_direction(model, quad, del, nws, r, dq));
  ad.newton_direction(x.qc, x.p, x.u, dq_ad);
  EXPECT_LT(rel(dq_ad, dq), 1e-8);
}

TEST(AutodiffDel, RejectsBodyWrenches) {
  Model m = models::pendulum(3);
  m.add_wrench(std::make_shared<BodyDrag>(1, 0.1, 0.1));
  EXPECT_THROW(AutodiffDel(m, Quadrature(2), 0.01), ModelError);
}

TEST(AutodiffDel, RejectsWrongSizes) {
  const Model m = models::pendulum(3);
  AutodiffDel ad(m, Quadrature(2), 0.01);
  MatX r, H;
  VecX pn;
  EXPECT_THROW(ad.residual(MatX::Zero(3, 2), VecX::Zero(3), MatX(0, 3), r, pn), InputError);
  EXPECT_THROW(ad.d2Ld(MatX::Zero(2, 3), H), InputError);
}

// Per-call times of the AD baseline and of hovi's recursive algorithms, Simpson rule (s = 2),
// pendulums n = 8, 32, 128 (Fig. 4 of the paper). Thread CPU time (robust to other load on the
// machine), median over batches. Run with --gtest_also_run_disabled_tests.
TEST(AutodiffDel, DISABLED_Timing) {
  auto cpu_now = [] {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
  };
  // Median of batches of calls, each batch lasting at least min_seconds / 5, after a warm-up call.
  auto time_call = [&](auto&& f, double min_seconds) {
    f();
    std::vector<double> samples;
    const double t_start = cpu_now();
    do {
      int reps = 0;
      const double t0 = cpu_now();
      double el;
      do {
        f();
        ++reps;
        el = cpu_now() - t0;
      } while (el < min_seconds / 5);
      samples.push_back(el / reps);
    } while (cpu_now() - t_start < min_seconds || samples.size() < 3);
    std::sort(samples.begin(), samples.end());
    return samples[samples.size() / 2];
  };
  std::printf("times per call in microseconds (thread CPU time); hovi newton = del_residual + newton_direction\n");
  std::printf("%5s %12s %12s %7s | %12s %12s %12s %7s | %12s %12s %7s\n", "n", "AD resid", "hovi resid", "ratio",
              "AD newton", "hovi newton", "(dir only)", "ratio", "AD d2Ld", "hovi d2Ld", "ratio");
  for (int n : {8, 32, 128}) {
    const Model model = models::pendulum(n);
    const SimpsonStep st(model, 0.01, 3);
    const Quadrature& quad = st.quad;
    const double dt = st.dt;
    const Sample& x = st.x;
    AutodiffDel ad(model, quad, dt);
    DelWorkspace del(model, quad);
    NewtonWorkspace nws(model, quad);
    DelJacobianWorkspace jws(model, quad);
    const int N = 3 * n;
    MatX r(n, 2), r_ad, dq(n, 2), dq_ad, H(N, N), H_ad;
    VecX pn(n), pn_ad;
    const double budget = n >= 128 ? 3.0 : 1.0;
    const double t_res_ad = time_call([&] { ad.residual(x.qc, x.p, x.u, r_ad, pn_ad); }, budget);
    const double t_res = time_call([&] { del_residual(model, quad, del, x.qc, x.p, x.u, dt, r, pn); }, 0.5);
    const double t_nd_ad = time_call([&] { ad.newton_direction(x.qc, x.p, x.u, dq_ad); }, budget);
    const double t_nd = time_call(
        [&] {
          del_residual(model, quad, del, x.qc, x.p, x.u, dt, r, pn);
          newton_direction(model, quad, del, nws, r, dq);
        },
        0.5);
    del_residual(model, quad, del, x.qc, x.p, x.u, dt, r, pn);
    const double t_dir = time_call([&] { newton_direction(model, quad, del, nws, r, dq); }, 0.5);
    const double t_h_ad = time_call([&] { ad.d2Ld(x.qc, H_ad); }, budget);
    const double t_h = time_call([&] { dlagrangian_hessian(model, quad, jws, x.qc, dt, H); }, 0.5);
    std::printf("%5d %12.2f %12.2f %7.0f | %12.1f %12.2f %12.2f %7.0f | %12.1f %12.2f %7.0f\n", n, 1e6 * t_res_ad,
                1e6 * t_res, t_res_ad / t_res, 1e6 * t_nd_ad, 1e6 * t_nd, 1e6 * t_dir, t_nd_ad / t_nd, 1e6 * t_h_ad,
                1e6 * t_h, t_h_ad / t_h);
    std::fflush(stdout);
    EXPECT_LT(rel(r_ad, r), 1e-10);
    EXPECT_LT(rel(dq_ad, dq), 1e-8);
    EXPECT_LT(rel(H_ad, H), 1e-9);
  }
}
