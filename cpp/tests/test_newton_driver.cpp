// The Newton iteration of every solver of hovi, on a fixed set of steps (several models, states,
// dt and s, with hard steps among them): the iterations, factorisations, residual evaluations and
// status of the integrator's NewtonSolver, the ConstrainedSolver, the Hermite-Simpson baseline,
// the quasi-Newton baseline and step_continuation are pinned: the figures of the solvers as they
// were before they shared one Newton driver (newton_driver.hpp, one stopping rule), which left them
// unchanged but for the quasi-Newton's stopping rule and the factorisation counts of the two
// baselines (see kHermiteSimpson and kQuasiNewton).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "test_models.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/baselines/hermite_simpson.hpp"
#include "hovi/baselines/quasi_newton.hpp"
#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/integrators/constrained_solver.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/integrators/step_continuation.hpp"
#include "hovi/models/pendulum.hpp"

using namespace hovi;

namespace {

constexpr double kPi = 3.14159265358979323846;

const char* const kStatusNames[] = {"Converged", "MaxIterations", "LineSearchFailed", "SingularJacobian",
                                    "NonFinite", "ContinuationStalled"};

struct Figures {
  int iterations, factorizations, residual_evaluations;
  SolveStatus status;
};

// Prints the figures in the form of the tables below (for re-recording) and compares.
void expect_figures(const char* table, const std::vector<Figures>& got, const std::vector<Figures>& want) {
  std::printf("  // %s\n", table);
  for (const Figures& f : got)
    std::printf("  {%d, %d, %d, SolveStatus::%s},\n", f.iterations, f.factorizations, f.residual_evaluations,
                kStatusNames[static_cast<int>(f.status)]);
  ASSERT_EQ(got.size(), want.size()) << table;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].iterations, want[i].iterations) << table << " case " << i;
    EXPECT_EQ(got[i].factorizations, want[i].factorizations) << table << " case " << i;
    EXPECT_EQ(got[i].residual_evaluations, want[i].residual_evaluations) << table << " case " << i;
    EXPECT_EQ(got[i].status, want[i].status) << table << " case " << i;
  }
}

Figures figures(const SolveInfo& info) {
  return {info.iterations, info.factorizations, info.residual_evaluations, info.status};
}

// A state (q, q̇) uniform in ±range and its momentum p = M(q) q̇.
struct State {
  VecX q, qdot, p;
};
State random_state(const Model& model, unsigned seed, double range) {
  std::mt19937 rng(seed);
  State st;
  st.q = test_models::uniform(rng, model.n(), -range, range);
  st.qdot = test_models::uniform(rng, model.n(), -range, range);
  Data data(model);
  st.p = mass_matrix(model, data, st.q) * st.qdot;
  return st;
}

// The guess q^{k,a} = q^k + c^a dt q̇^k.
MatX linear_guess(const Quadrature& quad, const State& st, double dt) {
  MatX qc(st.q.size(), quad.s + 1);
  for (int a = 0; a <= quad.s; ++a) qc.col(a) = st.q + quad.c[a] * dt * st.qdot;
  return qc;
}

SolverOptions fig2_options() {  // the Fig. 2 batch's Newton: residual tol 1e-10, 100 iterations
  SolverOptions opt;
  opt.tol = 1e-10;
  opt.max_iterations = 100;
  return opt;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Recorded before the solvers shared one Newton driver.
// ---------------------------------------------------------------------------------------------

const std::vector<Figures> kNewtonSolver = {
  {5, 1, 6, SolveStatus::Converged},
  {3, 3, 4, SolveStatus::Converged},
  {4, 1, 5, SolveStatus::Converged},
  {8, 1, 9, SolveStatus::Converged},
  {8, 2, 8, SolveStatus::Converged},
  {6, 2, 6, SolveStatus::Converged},
  {42, 39, 175, SolveStatus::LineSearchFailed},
  {14, 8, 16, SolveStatus::Converged},
  {30, 29, 126, SolveStatus::MaxIterations},
  {30, 28, 91, SolveStatus::MaxIterations},
};
const std::vector<Figures> kConstrained = {
  {4, 4, 4, SolveStatus::Converged},
  {5, 5, 5, SolveStatus::Converged},
  {5, 5, 5, SolveStatus::Converged},
  {5, 5, 5, SolveStatus::Converged},
};
// Before the redesign Hermite-Simpson's loop did not count its LU factorisations (0 in every row);
// the iterations, residual evaluations and status are those recorded.
const std::vector<Figures> kHermiteSimpson = {
  {2, 1, 3, SolveStatus::Converged},
  {3, 1, 4, SolveStatus::Converged},
  {3, 1, 4, SolveStatus::Converged},
  {5, 2, 5, SolveStatus::Converged},
  {3, 3, 4, SolveStatus::Converged},
  {5, 2, 5, SolveStatus::Converged},
  {4, 1, 5, SolveStatus::Converged},
  {3, 3, 4, SolveStatus::Converged},
  {6, 2, 6, SolveStatus::Converged},
};
// The quasi-Newton now stops on the rule of every solver (StoppingRule: step_tol 1e-15, and the
// error estimate θ/(1-θ) ||dq|| after a step); before, on its own ||dq||_inf <= 1e-14 (1 + ||q||_inf).
// Recorded before: the same rows, except 0 factorisations (not counted; J̃ is factored once) and
// row 7 (tol 1e-16, below round-off) {7, 0, 7, Converged}: 7 directions, the 7th at 1e-14; now
// the θ estimate stops after the 6th step.
const std::vector<Figures> kQuasiNewton = {
  {4, 1, 5, SolveStatus::Converged},
  {4, 1, 5, SolveStatus::Converged},
  {13, 1, 14, SolveStatus::NonFinite},
  {13, 1, 14, SolveStatus::NonFinite},
  {9, 1, 10, SolveStatus::NonFinite},
  {8, 1, 9, SolveStatus::NonFinite},
  {6, 1, 7, SolveStatus::Converged},
  {4, 1, 5, SolveStatus::Converged},
  {17, 1, 18, SolveStatus::Converged},
};
const std::vector<Figures> kContinuation = {
  {7, 9, 13, SolveStatus::Converged},
  {119, 136, 195, SolveStatus::ContinuationStalled},
  {138, 158, 227, SolveStatus::ContinuationStalled},
  {35, 37, 45, SolveStatus::Converged},
  {9, 11, 15, SolveStatus::Converged},
};

TEST(NewtonDriver, NewtonSolverFigures) {
  struct Case {
    Model model;
    int s;
    double dt, range;
    unsigned seed;
    SolverOptions opt;
  };
  SolverOptions dense, never, no_search, residual_tol;
  dense.direction = Direction::Dense;
  never.reuse = Reuse::Never;
  no_search.line_search = false;
  residual_tol.tol = 1e-9;
  const std::vector<Case> cases = {
      {models::pendulum(12), 3, 0.01, 0.5, 1, {}},
      {models::pendulum(12), 1, 0.01, 0.5, 2, never},
      {test_models::branched_tree(), 2, 0.02, 1.0, 3, {}},
      {test_models::forced_pendulum(), 4, 0.05, 1.0, 4, dense},
      {models::pendulum(8), 2, 0.1, 1.5, 5, no_search},
      {models::pendulum(8), 2, 0.1, 1.5, 5, residual_tol},
      {models::pendulum(32), 1, 0.06, kPi / 2, 11, fig2_options()},  // Fig. 2 states: hard steps
      {models::pendulum(32), 1, 0.06, kPi / 2, 12, fig2_options()},
      {models::pendulum(32), 1, 0.06, kPi / 2, 13, {}},
      {models::pendulum(32), 1, 0.03, kPi / 2, 14, {}},
  };
  std::vector<Figures> got;
  for (const Case& c : cases) {
    const Quadrature quad(c.s);
    const State st = random_state(c.model, c.seed, c.range);
    NewtonSolver solver(c.model, quad);
    MatX qc = linear_guess(quad, st, c.dt);
    MatX u = MatX::Constant(c.model.n_controls(), c.s + 1, 0.3);
    VecX p_next(c.model.n());
    got.push_back(figures(solver.solve(c.model, quad, c.opt, st.p, u, c.dt, qc, p_next)));
  }
  expect_figures("kNewtonSolver", got, kNewtonSolver);
}

TEST(NewtonDriver, ConstrainedSolverFigures) {
  struct Case {
    int links, s;
    double dt, range;
    unsigned seed;
    const char* axes;
  };
  const std::vector<Case> cases = {
      {4, 1, 0.01, 0.5, 21, "x"}, {4, 2, 0.02, 0.8, 22, "xz"}, {6, 3, 0.05, 1.0, 23, "xyz"},
      {6, 1, 0.1, 1.5, 24, "yz"},  // a long step
  };
  std::vector<Figures> got;
  for (const Case& c : cases) {
    Model model = models::pendulum(c.links);
    const State st = random_state(model, c.seed, c.range);
    // The tip held where it is at q^k (so that h(q^k) = 0).
    Data data(model);
    forward_kinematics(model, data, st.q);
    const Vec3 tip(0, 0, -0.25);
    model.add_constraint(std::make_shared<PointConstraint>(c.links - 1, tip, data.g[c.links - 1].act(tip), c.axes));
    const Quadrature quad(c.s);
    ConstrainedSolver solver(model, quad);
    MatX qc = linear_guess(quad, st, c.dt);
    MatX lambda = MatX::Zero(model.n_constraints(), c.s);
    VecX p_next(model.n());
    got.push_back(figures(solver.solve(SolverOptions(), st.p, MatX::Zero(0, c.s + 1), c.dt, qc, lambda, p_next)));
  }
  expect_figures("kConstrained", got, kConstrained);
}

TEST(NewtonDriver, HermiteSimpsonFigures) {
  struct Case {
    Model model;
    double dt, range;
    unsigned seed;
    HermiteSimpsonOptions opt;
  };
  HermiteSimpsonOptions fd, fresh, no_search, tight;
  fd.jacobian = HermiteSimpsonJacobian::FiniteDifference;
  fresh.reuse_jacobian = false;
  no_search.line_search = false;
  tight.tol = 1e-16;  // below round-off: stops on the step test
  HermiteSimpsonOptions tight_fresh = tight;
  tight_fresh.reuse_jacobian = false;
  const std::vector<Case> cases = {
      {models::pendulum(5), 0.01, 0.5, 31, {}},
      {test_models::forced_pendulum(), 0.05, 1.0, 32, {}},
      {test_models::forced_pendulum(), 0.05, 1.0, 32, fd},
      {models::pendulum(12), 0.1, 1.5, 33, {}},  // a long step
      {models::pendulum(12), 0.1, 1.5, 33, fresh},
      {models::pendulum(12), 0.1, 1.5, 33, no_search},
      {models::pendulum(8), 0.02, 1.0, 34, tight},
      {models::pendulum(8), 0.05, 1.0, 36, tight_fresh},
      {models::pendulum(32), 0.06, kPi / 2, 35, {}},
  };
  std::vector<Figures> got;
  for (const Case& c : cases) {
    const State st = random_state(c.model, c.seed, c.range);
    HermiteSimpson hs(c.model, c.dt, c.opt);
    const MatX u = MatX::Constant(c.model.n_controls(), 3, 0.3);
    VecX q1, v1;
    got.push_back(figures(hs.step(st.q, st.qdot, u, q1, v1)));
  }
  expect_figures("kHermiteSimpson", got, kHermiteSimpson);
}

TEST(NewtonDriver, QuasiNewtonFigures) {
  struct Case {
    Model model;
    double dt, range;
    unsigned seed;
    QuasiNewtonOptions opt;
  };
  const std::vector<Case> cases = {
      {models::pendulum(5), 0.01, 0.5, 41, {}},
      {test_models::branched_tree(), 0.01, 1.0, 42, {}},
      {models::pendulum(32), 0.01, kPi / 2, 43, {}},  // Fig. 2 states and options
      {models::pendulum(32), 0.02, kPi / 2, 44, {}},
      {models::pendulum(32), 0.03, kPi / 2, 45, {}},
      {models::pendulum(32), 0.06, kPi / 2, 46, {}},  // hard: diverges
      {models::pendulum(12), 0.01, 1.0, 47, QuasiNewtonOptions{1e-16, 300}},  // tol below round-off
      {models::pendulum(32), 0.002, kPi / 2, 48, {}},
      {models::pendulum(32), 0.005, kPi / 2, 49, QuasiNewtonOptions{1e-13, 300}},
  };
  std::vector<Figures> got;
  for (const Case& c : cases) {
    const Quadrature quad(1);
    const State st = random_state(c.model, c.seed, c.range);
    QuasiNewtonSolver qn(c.model, c.dt, c.opt);
    MatX qc = linear_guess(quad, st, c.dt);
    VecX p_next(c.model.n());
    got.push_back(figures(qn.solve(st.p, MatX::Zero(c.model.n_controls(), 2), qc, p_next)));
  }
  expect_figures("kQuasiNewton", got, kQuasiNewton);
}

TEST(NewtonDriver, ContinuationFigures) {
  struct Case {
    Model model;
    int s;
    double dt, range;
    unsigned seed;
    SolverOptions opt;
  };
  const std::vector<Case> cases = {
      {models::pendulum(8), 2, 0.01, 0.5, 51, {}},
      {models::pendulum(32), 1, 0.06, kPi / 2, 52, fig2_options()},  // Fig. 2: folds before dt
      {models::pendulum(32), 1, 0.06, kPi / 2, 53, fig2_options()},
      {models::pendulum(32), 1, 0.03, kPi / 2, 54, {}},
      {models::pendulum(12), 3, 0.1, 1.5, 55, {}},
  };
  std::vector<Figures> got;
  for (const Case& c : cases) {
    const Quadrature quad(c.s);
    const State st = random_state(c.model, c.seed, c.range);
    NewtonSolver solver(c.model, quad);
    MatX qc = linear_guess(quad, st, c.dt);
    VecX p_next(c.model.n());
    got.push_back(figures(step_continuation(solver, c.model, quad, c.opt, st.p, MatX::Zero(0, c.s + 1), c.dt, qc,
                                            p_next)));
  }
  expect_figures("kContinuation", got, kContinuation);
}
