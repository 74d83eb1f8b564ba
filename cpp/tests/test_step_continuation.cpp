// Continuation in the step length (step_continuation.hpp) on the setting of the paper's Fig. 2:
// the trapezoidal VI of the 32-link pendulum, q and q̇ uniform in [-π/2, π/2], dt = 0.06.
// References are computed here, never hard-coded: the physical branch by an independent
// natural-parameter continuation with 3000 uniform increments of h and plain Newton solves, the
// flow by 60 steps of the order-6 Galerkin integrator (s = 3) of length dt/60.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "test_models.hpp"
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/integrators/step_continuation.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

constexpr double kPi = 3.14159265358979323846;

double inf_norm(const MatX& x) { return x.cwiseAbs().maxCoeff(); }

struct Fig2 {
  Model model = models::pendulum(32);
  Quadrature quad{1};
  SolverOptions opt;
  NewtonSolver solver{model, quad};
  ContinuationWorkspace cws{model, quad};
  MatX u = MatX::Zero(0, 2);
  Fig2() {  // the Fig. 2 batch's Newton: residual tol 1e-10, 100 iterations
    opt.tol = 1e-10;
    opt.max_iterations = 100;
  }

  struct State {
    VecX q, qdot, p;
  };
  State state(std::mt19937& rng) {
    State st;
    st.q = test_models::uniform(rng, 32, -kPi / 2, kPi / 2);
    st.qdot = test_models::uniform(rng, 32, -kPi / 2, kPi / 2);
    Data data(model);
    st.p = mass_matrix(model, data, st.q) * st.qdot;
    return st;
  }
  // Plain Newton from q + dt q̇ (the Fig. 2 baseline).
  bool newton(const State& st, double dt) {
    MatX qc(32, 2);
    qc.col(0) = st.q;
    qc.col(1) = st.q + dt * st.qdot;
    VecX p_next(32);
    return solver.solve(model, quad, opt, st.p, u, dt, qc, p_next).converged();
  }
  SolveInfo continuation(const State& st, double dt, MatX& qc, VecX& p_next, ContinuationReport* rep = nullptr) {
    qc.resize(32, 2);
    qc.col(0) = st.q;
    qc.col(1).setConstant(1e3);  // ignored: the path starts from q^k
    p_next.resize(32);
    return step_continuation(solver, cws, model, quad, opt, st.p, u, dt, qc, p_next, {}, rep);
  }
  // The physical branch, independently: h_j = j dt / steps, Newton without line search from the
  // secant predictor through the two previous points. Returns the last h reached.
  double dense_path(const State& st, double dt, int steps, VecX& q_end) {
    SolverOptions o = opt;
    o.line_search = false;
    o.max_iterations = 6;
    NewtonSolver newton(model, quad);
    VecX back = st.q, cur = st.q, p_next(32);
    double h_cur = 0;
    MatX qc(32, 2);
    qc.col(0) = st.q;
    for (int j = 1; j <= steps; ++j) {
      const double h = dt * j / steps;
      qc.col(1) = j == 1 ? VecX(st.q + h * st.qdot) : VecX(cur + (cur - back));
      if (!newton.solve(model, quad, o, st.p, u, h, qc, p_next).converged()) break;
      back = cur;
      cur = qc.col(1);
      h_cur = h;
    }
    q_end = cur;
    return h_cur;
  }
  // The exact flow at t = dt (to ~1e-12): 60 steps of the order-6 Galerkin VI.
  VecX flow(const State& st, double dt) {
    GalerkinIntegrator vi(model, 3, dt / 60);
    const Rollout r = vi.rollout(st.q, st.p, 60, MatX(60, 0));
    EXPECT_EQ(r.steps, 60);
    return r.q.row(60).transpose();
  }
  double residual(const State& st, const MatX& qc, double dt) {
    MatX r(32, 1);
    VecX p_next(32);
    DelWorkspace del(model, quad);
    del_residual(model, quad, del, qc, st.p, u, dt, r, p_next);
    return inf_norm(r);
  }
};

}  // namespace

// sign det J from the pivot blocks of Algorithm A.2 equals that of the dense DEL Jacobian, for
// both signs, several s and a branched tree; and as h -> 0 it is small_step_determinant_sign.
TEST(StepContinuation, DeterminantSignFromPivots) {
  std::mt19937 rng(7);
  for (int which = 0; which < 2; ++which)
    for (int s = 1; s <= 3; ++s) {
      const Model model = which == 0 ? models::pendulum(8) : test_models::branched_tree();
      const int n = model.n();
      const Quadrature quad(s);
      DelWorkspace del(model, quad);
      NewtonWorkspace nw(model, quad);
      DelJacobianWorkspace jw(model, quad);
      MatX r(n, s), u = MatX::Zero(0, s + 1), Jq((s + 1) * n, (s + 1) * n);
      VecX p = VecX::Zero(n), p_next(n);
      int seen[2] = {0, 0};
      for (int trial = 0; trial < 60; ++trial) {
        const VecX q0 = test_models::uniform(rng, n, -1.5, 1.5), v = test_models::uniform(rng, n, -4, 4);
        const double dt = std::uniform_real_distribution<double>(0.01, 0.4)(rng);
        MatX qc(n, s + 1);
        for (int a = 0; a <= s; ++a)
          qc.col(a) = q0 + quad.c[a] * dt * v + (a > 0 ? 0.3 : 0.0) * test_models::uniform(rng, n, -1, 1);
        del_residual(model, quad, del, qc, p, u, dt, r, p_next);
        ASSERT_TRUE(newton_factor(model, quad, del, nw));
        del_jacobian(model, quad, jw, qc, u, dt, Jq, nullptr);
        const double det = Jq.block(0, n, s * n, s * n).partialPivLu().determinant();
        const int sign = jacobian_determinant_sign(nw);
        EXPECT_EQ(sign, det > 0 ? 1 : -1) << "model " << which << " s=" << s << " trial " << trial;
        ++seen[sign > 0];
      }
      if (which == 0) {  // both signs were exercised (the tree's J keeps one sign on these samples)
        EXPECT_GT(seen[0], 0) << "s=" << s;
        EXPECT_GT(seen[1], 0) << "s=" << s;
      }
      // h -> 0 at rest: the kinetic term dominates.
      MatX qc(n, s + 1);
      qc.colwise() = VecX(test_models::uniform(rng, n, -1, 1));
      del_residual(model, quad, del, qc, p, u, 1e-6, r, p_next);
      ASSERT_TRUE(newton_factor(model, quad, del, nw));
      EXPECT_EQ(jacobian_determinant_sign(nw), small_step_determinant_sign(quad, n)) << "model " << which << " s=" << s;
    }
}

// Where the step is easy, continuation returns Newton's root (same stopping rule), for the
// trapezoidal and the Simpson integrator, and from rest (q̇ = 0, where the branch starts with a
// zero tangent).
TEST(StepContinuation, AgreesWithNewtonOnEasySteps) {
  std::mt19937 rng(3);
  for (int s = 1; s <= 2; ++s) {
    const Model model = models::pendulum(8);
    const Quadrature quad(s);
    NewtonSolver solver(model, quad);
    const MatX u = MatX::Zero(0, s + 1);
    SolverOptions opt;
    Data data(model);
    for (int trial = 0; trial < 10; ++trial) {
      const VecX q = test_models::uniform(rng, 8, -1.5, 1.5);
      const VecX qdot = trial < 2 ? VecX(VecX::Zero(8)) : test_models::uniform(rng, 8, -1.5, 1.5);
      const VecX p = mass_matrix(model, data, q) * qdot;
      const double dt = 0.005;
      MatX qn(8, s + 1), qc(8, s + 1);
      for (int a = 0; a <= s; ++a) qn.col(a) = q + quad.c[a] * dt * qdot;
      VecX pn(8), pc(8);
      ASSERT_TRUE(solver.solve(model, quad, opt, p, u, dt, qn, pn).converged());
      qc.col(0) = q;
      qc.rightCols(s).setZero();
      ContinuationReport rep;
      const SolveInfo info = step_continuation(solver, model, quad, opt, p, u, dt, qc, pc, {}, &rep);
      ASSERT_TRUE(info.converged()) << to_string(info.status) << " s=" << s << " trial " << trial;
      EXPECT_LT(inf_norm(qc - qn), 1e-9) << "s=" << s << " trial " << trial;
      EXPECT_LT(inf_norm(pc - pn), 1e-8 * (1 + inf_norm(pn)));
      EXPECT_EQ(rep.h_reached, dt);
      EXPECT_LE(rep.steps, 3);  // the probe, the rest of the step at once (maybe one halving)
    }
  }
}

// Fig. 2 at dt = 0.06: a state where plain Newton fails but the physical branch reaches dt.
// The continuation converges there; its root has a residual below tolerance, is the end of the
// independently computed dense path, and belongs to the family of roots that converges to the
// flow as h -> 0 (local error ~ h^3: divided by more than 4 from dt/4 to dt/8 and again to
// dt/16, where a root off that family would not converge at all).
TEST(StepContinuation, ConvergesOnTheBranchWhereNewtonFails) {
  Fig2 f;
  const double dt = 0.06;
  std::mt19937 rng(2018);
  int tried = 0, found = 0;
  for (; tried < 400 && found < 1; ++tried) {
    const Fig2::State st = f.state(rng);
    if (f.newton(st, dt)) continue;
    MatX qc;
    VecX p_next;
    ContinuationReport rep;
    const SolveInfo info = f.continuation(st, dt, qc, p_next, &rep);
    EXPECT_TRUE(info.converged() || info.status == SolveStatus::ContinuationStalled) << to_string(info.status);
    if (!info.converged()) continue;
    ++found;
    EXPECT_LE(f.residual(st, qc, dt), f.opt.tol * (1 + inf_norm(st.p)));
    EXPECT_TRUE(qc.allFinite() && p_next.allFinite());
    VecX q_dense;
    ASSERT_EQ(f.dense_path(st, dt, 3000, q_dense), dt) << "the dense path stops before dt";
    EXPECT_LT(inf_norm(qc.col(1) - q_dense), 1e-8) << "not the root on the physical branch";
    double previous_error = 0;
    for (int k : {4, 8, 16}) {
      MatX qh;
      VecX ph;
      ASSERT_TRUE(f.continuation(st, dt / k, qh, ph).converged());
      const double error = inf_norm(qh.col(1) - f.flow(st, dt / k));
      if (k > 4) {
        EXPECT_LT(error, previous_error / 4) << "dt/" << k;  // local error O(h^3): ratios 6.3, 7.3 here
      }
      previous_error = error;
    }
    const double error = inf_norm(qc.col(1) - f.flow(st, dt)), motion = inf_norm(f.flow(st, dt) - st.q);
    RecordProperty("state", tried);
    RecordProperty("error_vs_flow_x1e6", static_cast<int>(error * 1e6));
    RecordProperty("motion_x1e6", static_cast<int>(motion * 1e6));
  }
  EXPECT_EQ(found, 1) << "no state among " << tried << " where Newton fails and the branch reaches dt";
}

// A step whose branch turns back before dt (a fold) ends with ContinuationStalled, with finite
// numbers and bounded work, at the h where the dense path stops too; so does dt = 1 s; and a
// non-finite momentum ends with NonFinite.
TEST(StepContinuation, FoldEndsWithAnExplicitFailure) {
  Fig2 f;
  const double dt = 0.06;
  std::mt19937 rng(2018);
  int checked = 0;
  for (int tried = 0; tried < 50 && checked < 3; ++tried) {
    const Fig2::State st = f.state(rng);
    MatX qc;
    VecX p_next;
    ContinuationReport rep;
    const SolveInfo info = f.continuation(st, dt, qc, p_next, &rep);
    if (info.converged()) continue;
    ++checked;
    EXPECT_EQ(info.status, SolveStatus::ContinuationStalled);
    EXPECT_TRUE(qc.allFinite() && p_next.allFinite() && std::isfinite(info.residual));
    EXPECT_GT(info.residual, f.opt.tol * (1 + inf_norm(st.p)));
    EXPECT_LT(rep.h_reached, dt);
    EXPECT_LE(info.iterations, ContinuationOptions().max_iterations + 8);
    // qc is the last point of the branch: a root at h_reached.
    EXPECT_LE(f.residual(st, qc, rep.h_reached), f.opt.tol * (1 + inf_norm(st.p)));
    // The dense path (increments dt/3000) stops within two increments of the same h.
    VecX q_dense;
    const double h_dense = f.dense_path(st, dt, 3000, q_dense);
    EXPECT_LT(h_dense, dt);
    EXPECT_NEAR(h_dense, rep.h_reached, 2 * dt / 3000) << "state " << tried;
    // A step of a whole second from the same state.
    const SolveInfo far = f.continuation(st, 1.0, qc, p_next, &rep);
    EXPECT_EQ(far.status, SolveStatus::ContinuationStalled);
    EXPECT_TRUE(qc.allFinite() && p_next.allFinite());
    EXPECT_LT(rep.h_reached, 0.06);
  }
  EXPECT_EQ(checked, 3);
  Fig2::State st = f.state(rng);
  st.p[3] = NAN;
  MatX qc;
  VecX p_next;
  EXPECT_EQ(f.continuation(st, dt, qc, p_next).status, SolveStatus::NonFinite);
}

// step tries the continuation last: every step ends converged (with a small residual) or
// with ContinuationStalled.
TEST(StepContinuation, RobustStepEndsWithContinuation) {
  Fig2 f;
  GalerkinIntegrator vi(models::pendulum(32), 1, 0.06);
  std::mt19937 rng(11);
  int stalled = 0;
  for (int k = 0; k < 20; ++k) {
    const Fig2::State st = f.state(rng);
    MatX qc(32, 2);
    qc.col(0) = st.q;
    VecX p_next(32);
    StepHistory h;
    const SolveInfo info = vi.step(st.p, f.u, qc, p_next, h);
    if (info.converged()) {
      EXPECT_LE(f.residual(st, qc, 0.06), 1e-10 * (1 + inf_norm(st.p)));  // converged (at round-off)
    } else {
      EXPECT_EQ(info.status, SolveStatus::ContinuationStalled);
      EXPECT_TRUE(qc.allFinite() && p_next.allFinite());
      ++stalled;
    }
  }
  EXPECT_GT(stalled, 0);
}
