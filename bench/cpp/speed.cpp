// Per-call times of hovi's DEL evaluation (Algorithm 1), Newton direction (A.1/A.2), a full
// converged step and a 1000-step rollout, against Pinocchio's rnea and aba on the same
// kinematic tree, all in this one process. Prints one JSON object per line.
//
//   hovi_bench_speed pendulum N S...     the built-in N-link pendulum
//   hovi_bench_speed urdf PATH S...      a URDF (fixed base), loaded by hovi and handed to Pinocchio
//   hovi_bench_speed skip PATH           DEL evaluation with and without force elements / gravity
//   hovi_bench_speed lin-pendulum N S... / lin-urdf PATH S...
//                                        linearisation: D^2 L_d, DEL Jacobian, step Jacobians A, (A, B),
//                                        against Pinocchio's computeRNEADerivatives
//   hovi_bench_speed constrained N S M... the constrained Newton direction on the N-link pendulum with
//                                        M single-axis point constraints spread along the chain
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/integrators/constrained_solver.hpp"
#include "hovi/integrators/linearizer.hpp"
#include "hovi/models/pendulum.hpp"
#include "hovi/parsers/urdf.hpp"

using namespace hovi;
using Clock = std::chrono::steady_clock;

namespace {

// Median over 7 batches of the mean time per call, each batch at least ~20 ms.
double time_per_call(const std::function<void()>& f) {
  f();
  int reps = 1;
  for (;;) {
    const auto t0 = Clock::now();
    for (int k = 0; k < reps; ++k) f();
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    if (dt > 0.02) break;
    reps *= 2;
  }
  std::vector<double> t;
  for (int b = 0; b < 7; ++b) {
    const auto t0 = Clock::now();
    for (int k = 0; k < reps; ++k) f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count() / reps);
  }
  std::nth_element(t.begin(), t.begin() + 3, t.end());
  return t[3];
}

// The same tree in Pinocchio: joint frames and inertias exactly as hovi's BodySpecs.
pinocchio::Model to_pinocchio(const Model& m) {
  pinocchio::Model pm;
  for (int i = 0; i < m.n(); ++i) {
    const BodySpec& s = m.spec[i];
    const pinocchio::SE3 X(s.placement.R, s.placement.p);
    const int parent = s.parent + 1;
    pinocchio::JointIndex j;
    if (s.type == JointType::Revolute)
      j = pm.addJoint(parent, pinocchio::JointModelRevoluteUnaligned(s.axis), X, s.joint_name);
    else
      j = pm.addJoint(parent, pinocchio::JointModelPrismaticUnaligned(s.axis), X, s.joint_name);
    pm.appendBodyToJoint(j, pinocchio::Inertia(s.mass, s.com, s.inertia), pinocchio::SE3::Identity());
  }
  pm.gravity.linear(m.gravity);
  return pm;
}

struct Bench {
  const Model& model;
  std::string name;
  std::mt19937 rng{42};
  VecX random(int n, double a) {
    std::uniform_real_distribution<double> d(-a, a);
    VecX x(n);
    for (int i = 0; i < n; ++i) x[i] = d(rng);
    return x;
  }

  void reference_line() {
    const int n = model.n();
    pinocchio::Model pm = to_pinocchio(model);
    pinocchio::Data pd(pm);
    Data data(model);
    const VecX q = random(n, 1.5), v = random(n, 1.5), a = random(n, 1.5), tau = random(n, 1.5);
    // The trees agree (else the ratios would be meaningless).
    const double diff = (pinocchio::rnea(pm, pd, q, v, a) - inverse_dynamics(model, data, q, v, a)).cwiseAbs().maxCoeff();
    const double t_rnea = time_per_call([&] { pinocchio::rnea(pm, pd, q, v, a); });
    const double t_aba = time_per_call([&] { pinocchio::aba(pm, pd, q, v, tau); });
    const double t_hovi_aba = time_per_call([&] { forward_dynamics(model, data, q, v, tau); });
    std::printf("{\"model\": \"%s\", \"n\": %d, \"op\": \"reference\", \"pin_rnea\": %.6e, \"pin_aba\": %.6e, "
                "\"hovi_aba\": %.6e, \"rnea_max_diff\": %.3e}\n",
                name.c_str(), n, t_rnea, t_aba, t_hovi_aba, diff);
  }

  void integrator_line(int s, double dt) {
    const int n = model.n();
    GalerkinIntegrator integ(model, s, dt);
    const Quadrature& quad = integ.quadrature();
    DelWorkspace del(model, quad);
    NewtonWorkspace nws(model, quad);
    // A realistic point: a converged step from a random state.
    // A gentle state (the paper's Fig. 4 range, at rest) so that rollouts stay resolved at dt.
    const VecX q0 = random(n, M_PI / 12), qd0 = VecX::Zero(n);
    const VecX p0 = integ.momentum(q0, qd0);
    MatX qc(n, s + 1), r(n, s), dq(n, s), u(model.n_controls(), s + 1);
    u.setZero();
    VecX pn(n);
    qc.col(0) = q0;
    integ.guess_from_velocity(qd0, qc);
    const MatX guess = qc;
    const double t_eval = time_per_call([&] { del_residual(model, quad, del, guess, p0, u, dt, r, pn); });
    del_residual(model, quad, del, guess, p0, u, dt, r, pn);
    const double t_dir = time_per_call([&] { newton_direction(model, quad, del, nws, r, dq); });
    SolveInfo info;
    const double t_step = time_per_call([&] {
      qc = guess;
      info = integ.solve(p0, u, qc, pn);
    });
    const int N = 1000;
    MatX U(N, (s + 1) * model.n_controls());
    U.setZero();
    const auto t0 = Clock::now();
    const Rollout ro = integ.rollout(q0, p0, N, U);
    const double t_roll = std::chrono::duration<double>(Clock::now() - t0).count();
    std::printf("{\"model\": \"%s\", \"n\": %d, \"s\": %d, \"dt\": %g, \"op\": \"integrator\", \"del_residual\": %.6e, "
                "\"newton_direction\": %.6e, \"step\": %.6e, \"step_iterations\": %d, \"step_converged\": %s, "
                "\"rollout_1000\": %.6e, \"rollout_steps\": %d, \"rollout_mean_iterations\": %.3f}\n",
                name.c_str(), n, s, dt, t_eval, t_dir, t_step, info.iterations, info.converged() ? "true" : "false",
                t_roll, ro.steps, ro.iterations.head(std::max(ro.steps, 1)).cast<double>().mean());
  }

  void linearization_line(int s, double dt) {
    const int n = model.n();
    pinocchio::Model pm = to_pinocchio(model);
    pinocchio::Data pd(pm);
    const VecX q = random(n, 1.5), v = random(n, 1.5), a = random(n, 1.5);
    const double t_rnead = time_per_call([&] { pinocchio::computeRNEADerivatives(pm, pd, q, v, a); });
    GalerkinIntegrator integ(model, s, dt);
    const Quadrature& quad = integ.quadrature();
    DelJacobianWorkspace ws(model, quad);
    Linearizer lin(integ);
    const VecX q0 = random(n, M_PI / 12), qd0 = VecX::Zero(n);
    MatX qc(n, s + 1), u = MatX::Zero(model.n_controls(), s + 1), H((s + 1) * n, (s + 1) * n), Jq, A, B;
    VecX pn(n);
    qc.col(0) = q0;
    integ.guess_from_velocity(qd0, qc);
    integ.solve(integ.momentum(q0, qd0), u, qc, pn);  // converged control points
    const double t_d2l = time_per_call([&] { dlagrangian_hessian(model, quad, ws, qc, dt, H); });
    const double t_jac = time_per_call([&] { lin.del_jacobian(qc, u, Jq, nullptr); });
    const double t_A = time_per_call([&] { lin.step_jacobians(qc, u, &A, nullptr); });
    const double t_AB = time_per_call([&] { lin.step_jacobians(qc, u, &A, &B); });
    std::printf("{\"model\": \"%s\", \"n\": %d, \"s\": %d, \"op\": \"linearization\", \"pin_rnea_derivatives\": %.6e, "
                "\"d2Ld\": %.6e, \"del_jacobian\": %.6e, \"step_A\": %.6e, \"step_AB\": %.6e}\n",
                name.c_str(), n, s, t_rnead, t_d2l, t_jac, t_A, t_AB);
  }
};

// One constrained Newton direction (factor, 1 + s m recursive solves, Schur complement) and one
// constrained residual evaluation, with m single-axis point constraints on bodies spread along
// the chain (targets at the current configuration, so the constraints are consistent).
void constrained_lines(int n, int s, const std::vector<int>& ms) {
  for (int m : ms) {
    Model model = models::pendulum(n);
    Data data(model);
    Bench b{model, "pendulum"};
    const VecX q0 = b.random(n, M_PI / 12);
    forward_kinematics(model, data, q0);
    const char* axes[3] = {"x", "y", "z"};
    for (int k = 0; k < m; ++k) {
      const int body = (k + 1) * n / (m + 1);
      const Vec3 tip(0, 0, -0.25);  // below the COM, in its frame
      model.add_constraint(std::make_shared<PointConstraint>(body, tip, data.g[body].act(tip), axes[k % 3]));
    }
    GalerkinIntegrator integ(model, s, 0.01);
    ConstrainedSolver cs(model, integ.quadrature());
    MatX qc(n, s + 1), lam = MatX::Zero(m, s), u(0, s + 1), r, H, dz, dl;
    qc.col(0) = q0;
    integ.guess_from_velocity(VecX::Zero(n), qc);
    VecX pn(n);
    const VecX p0 = VecX::Zero(n);
    cs.evaluate(p0, u, lam, 0.01, qc, r, H, pn);
    const double t_eval = time_per_call([&] { cs.evaluate(p0, u, lam, 0.01, qc, r, H, pn); });
    cs.evaluate(p0, u, lam, 0.01, qc, r, H, pn);
    bool ok = true;
    const double t_dir = time_per_call([&] { ok = cs.direction(0.01, r, H, dz, dl) && ok; });
    std::printf("{\"model\": \"pendulum\", \"n\": %d, \"s\": %d, \"m\": %d, \"op\": \"constrained\", "
                "\"residual\": %.6e, \"direction\": %.6e, \"ok\": %s}\n",
                n, s, m, t_eval, t_dir, ok ? "true" : "false");
  }
}

// DEL evaluation cost with and without the work a scene may or may not need.
void skip_lines(const Model& base, const std::string& name, int s) {
  auto eval_time = [&](const Model& m) {
    Bench b{m, name};
    const int n = m.n();
    Quadrature quad(s);
    DelWorkspace del(m, quad);
    MatX qc(n, s + 1), r(n, s), u = MatX::Zero(m.n_controls(), s + 1);
    for (int a = 0; a <= s; ++a) qc.col(a) = b.random(n, 0.5);
    const VecX p = b.random(n, 0.5);
    VecX pn(n);
    return time_per_call([&] { del_residual(m, quad, del, qc, p, u, 0.01, r, pn); });
  };
  Model no_gravity = base;
  no_gravity.gravity.setZero();
  Model forced = base;
  for (int i = 0; i < forced.n(); ++i) {
    forced.add_spring(i, 10.0, 0.0);
    forced.add_damper(i, 0.1);
    forced.add_actuator(i);
  }
  for (int i = 0; i < forced.n(); i += 4) forced.add_wrench(std::make_shared<BodyDrag>(i, 0.1, 0.01));
  std::printf("{\"model\": \"%s\", \"n\": %d, \"s\": %d, \"op\": \"skip\", \"gravity_only\": %.6e, "
              "\"no_forces\": %.6e, \"all_forces\": %.6e}\n",
              name.c_str(), base.n(), s, eval_time(base), eval_time(no_gravity), eval_time(forced));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: hovi_bench_speed pendulum N S... | urdf PATH S... | skip PATH\n";
    return 2;
  }
  const std::string kind = argv[1];
  if (kind == "constrained") {
    std::vector<int> ms;
    for (int k = 4; k < argc; ++k) ms.push_back(std::stoi(argv[k]));
    constrained_lines(std::stoi(argv[2]), std::stoi(argv[3]), ms);
    return 0;
  }
  const bool pendulum = kind == "pendulum" || kind == "lin-pendulum";
  Model model = pendulum ? models::pendulum(std::stoi(argv[2])) : model_from_urdf(argv[2]);
  const std::string name = pendulum ? "pendulum" : std::string(argv[2]).substr(std::string(argv[2]).rfind('/') + 1);
  if (kind == "skip") {
    skip_lines(model, name, 2);
    return 0;
  }
  Bench b{model, name};
  if (kind.rfind("lin-", 0) == 0) {
    for (int k = 3; k < argc; ++k) b.linearization_line(std::stoi(argv[k]), 0.01);
    return 0;
  }
  b.reference_line();
  for (int k = 3; k < argc; ++k) b.integrator_line(std::stoi(argv[k]), 0.01);
  return 0;
}
