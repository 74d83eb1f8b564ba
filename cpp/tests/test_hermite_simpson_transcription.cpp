// The Hermite-Simpson transcription (trajopt/hermite_simpson_transcription.hpp), implicit and
// explicit forms: input checks; variable and constraint counts against the paper's Table 1;
// the Jacobian against central differences of constraints() and its sparsity structure against
// the differences' nonzeros (both forms, both control modes, unconstrained and constrained, with
// springs, dampers, actuators and body wrenches); the constraints vanish at converged steps of the
// Hermite-Simpson baseline simulator; concurrent calls agree with serial ones.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "test_models.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/baselines/hermite_simpson.hpp"
#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/errors.hpp"
#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/model/data.hpp"
#include "hovi/models/pendulum.hpp"
#include "hovi/trajopt/hermite_simpson_transcription.hpp"

using namespace hovi;

namespace {

using test_models::forced_pendulum;
using test_models::uniform;

// The branched tree (prismatic joints, skewed axes, offset COMs) with springs, dampers and actuators.
Model forced_tree() {
  return test_models::with_forces(test_models::branched_tree(), {{1, 2.0, 0.1}, {4, 1.0, -0.3}}, {{0, 0.3}, {5, 0.5}},
                                  {{0, 1.0}, {3, 0.5}, {5, 1.5}});
}

// A world point of body `body` (a point r in its COM frame) at configuration q.
Vec3 world_point(const Model& model, const VecX& q, int body, const Vec3& r) {
  Data data(model);
  forward_kinematics(model, data, q);
  return data.g[body].R * r + data.g[body].p;
}

// The n-link pendulum, fully actuated (Table 1's setting), with its tip held in the horizontal
// plane's x and y (m_c = 2) at its position at q0.
Model constrained_pendulum(int n, const VecX& q0) {
  Model m = models::pendulum(n);
  for (int j = 0; j < n; ++j) m.add_actuator(j);
  m.add_spring(0, 1.0, 0.1);
  m.add_damper(1, 0.2);
  const Vec3 r(0, 0, -0.25);  // the link's lower end (length 0.5, COM at its middle)
  m.add_constraint(std::make_shared<PointConstraint>(n - 1, r, world_point(m, q0, n - 1, r), "xy"));
  return m;
}

// The branched tree with a full point constraint (m_c = 3) and a joint coupling (m_c = 1), its
// springs, dampers and actuators.
Model constrained_tree() {
  Model m = forced_tree();
  const VecX q0 = VecX::Constant(m.n(), 0.1);
  const Vec3 r(0.1, 0.0, -0.1);
  m.add_constraint(std::make_shared<PointConstraint>(2, r, world_point(m, q0, 2, r), "xyz"));
  VecX c = VecX::Zero(m.n());
  c[4] = 1.0;
  c[5] = -0.5;
  m.add_constraint(std::make_shared<JointCoupling>(c, 0.05));
  return m;
}

// The forced pendulum with body wrenches: a drag on one body and a world-frame point force
// scaled by a control input (no actuation, only used by the wrench).
Model pendulum_with_wrenches() {
  Model m = forced_pendulum();
  m.add_wrench(std::make_shared<BodyDrag>(2, 0.3, 0.1));
  const int u = m.add_control();
  m.add_wrench(std::make_shared<PointWrench>(4, Vec3(0.01, 0.02, -0.1), Vec3(1.0, -0.5, 0.3), Vec3(0.1, 0.2, 0.0),
                                             PointWrench::Frame::World, u));
  return m;
}

// A random x, every block filled (q, v in [-1, 1], a in [-3, 3], u, λ in [-1, 1]).
VecX random_x(const HermiteSimpsonTranscription& tr, const Model& model, std::mt19937& rng) {
  const int n = model.n(), P = tr.n_points();
  VecX x = uniform(rng, tr.n_variables(), -1, 1);
  if (tr.implicit()) x.segment(tr.a_offset(), P * n) = uniform(rng, P * n, -3, 3);
  return x;
}

// Central differences of constraints() in every variable, n_constraints x n_variables.
MatX fd_jacobian(const Transcription& tr, const VecX& x) {
  MatX J(tr.n_constraints(), tr.n_variables());
  VecX xp = x, xm = x, gp(tr.n_constraints()), gm(tr.n_constraints());
  for (int j = 0; j < tr.n_variables(); ++j) {
    const double eps = 1e-6 * (1 + std::abs(x[j]));
    xp[j] = x[j] + eps;
    xm[j] = x[j] - eps;
    tr.constraints(xp, gp);
    tr.constraints(xm, gm);
    J.col(j) = (gp - gm) / (2 * eps);
    xp[j] = xm[j] = x[j];
  }
  return J;
}

// The Jacobian's values scattered into a dense matrix (duplicates would add; they are checked
// absent separately).
MatX dense_jacobian(const Transcription& tr, const VecX& x) {
  const SparsityStructure& s = tr.structure();
  VecX values(s.nnz());
  tr.jacobian(x, values);
  MatX J = MatX::Zero(tr.n_constraints(), tr.n_variables());
  for (int k = 0; k < s.nnz(); ++k) J(s.rows[k], s.cols[k]) += values[k];
  return J;
}

void check_structure_well_formed(const Transcription& tr) {
  const SparsityStructure& s = tr.structure();
  ASSERT_EQ(s.rows.size(), s.cols.size());
  std::set<std::pair<int, int>> seen;
  for (int k = 0; k < s.nnz(); ++k) {
    ASSERT_GE(s.rows[k], 0);
    ASSERT_LT(s.rows[k], tr.n_constraints());
    ASSERT_GE(s.cols[k], 0);
    ASSERT_LT(s.cols[k], tr.n_variables());
    ASSERT_TRUE(seen.emplace(s.rows[k], s.cols[k]).second) << "duplicate entry (" << s.rows[k] << ", " << s.cols[k] << ")";
  }
}

// The Jacobian's values against central differences at a random x (relative 1e-6 of the largest
// entry), and every difference above 1e-9 inside the structure.
void check_jacobian(const Model& model, int N, double dt, ControlMode mode, bool implicit, std::mt19937& rng,
                    const std::string& label) {
  SCOPED_TRACE(label + (implicit ? " implicit" : " explicit") +
               (mode == ControlMode::PerPoint ? " per-point" : " held") + " N " + std::to_string(N));
  HermiteSimpsonTranscription tr(model, N, dt, mode, implicit);
  check_structure_well_formed(tr);
  const VecX x = random_x(tr, model, rng);
  const MatX Jfd = fd_jacobian(tr, x);
  const MatX J = dense_jacobian(tr, x);
  const double scale = Jfd.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  Eigen::Index r, c;
  const double err = (J - Jfd).cwiseAbs().maxCoeff(&r, &c);
  EXPECT_LT(err, 1e-6 * scale) << "at (" << r << ", " << c << "): " << J(r, c) << " vs FD " << Jfd(r, c)
                               << ", largest entry " << scale;
  std::set<std::pair<int, int>> in;
  const SparsityStructure& s = tr.structure();
  for (int k = 0; k < s.nnz(); ++k) in.emplace(s.rows[k], s.cols[k]);
  int outside = 0;
  for (int j = 0; j < Jfd.cols(); ++j)
    for (int i = 0; i < Jfd.rows(); ++i)
      if (std::abs(Jfd(i, j)) > 1e-9 && !in.count({i, j})) {
        if (++outside <= 5) ADD_FAILURE() << "FD nonzero " << Jfd(i, j) << " at (" << i << ", " << j << ") outside the structure";
      }
  EXPECT_EQ(outside, 0);
}

}  // namespace

TEST(HermiteSimpsonTranscription, InputChecks) {
  const Model model = forced_pendulum();
  for (bool implicit : {true, false}) {
    EXPECT_THROW(HermiteSimpsonTranscription(model, 0, 0.1, ControlMode::PerPoint, implicit), InputError);
    EXPECT_THROW(HermiteSimpsonTranscription(model, -3, 0.1, ControlMode::Held, implicit), InputError);
    for (double dt : {0.0, -0.1, std::nan(""), double(INFINITY)})
      EXPECT_THROW(HermiteSimpsonTranscription(model, 2, dt, ControlMode::PerPoint, implicit), InputError) << dt;
    EXPECT_THROW(HermiteSimpsonTranscription(Model(), 2, 0.1, ControlMode::PerPoint, implicit), ModelError);
    HermiteSimpsonTranscription tr(model, 2, 0.1, ControlMode::PerPoint, implicit);
    VecX g(tr.n_constraints()), values(tr.structure().nnz());
    EXPECT_THROW(tr.constraints(VecX::Zero(tr.n_variables() + 1), g), InputError);
    VecX short_values(values.size() - 1);
    EXPECT_THROW(tr.jacobian(VecX::Zero(tr.n_variables()), short_values), InputError);
  }
}

// Offsets and counts. Table 1 (N stages, n DoF, fully actuated with n inputs, m holonomic
// constraint equations): variables explicit (6N+3)n + (2N+1)m, implicit (8N+4)n + (2N+1)m (the
// n inputs per point are inside the n terms); constraints explicit 4Nn + (6N+3)m, implicit
// (6N+1)n + (6N+3)m. The variables match exactly; the constraints match exactly without
// constraints. With constraints the paper imposes h, ḣ and ḧ at every point; hovi's transcription
// (by design, see its header) imposes ḧ at every point and h, ḣ only at t = 0, so it has
// (2N+3)m rows there instead of (6N+3)m: 4Nm fewer.
TEST(HermiteSimpsonTranscription, CountsMatchTable1) {
  for (int N : {1, 2, 7}) {
    for (int n : {3, 4}) {
      const VecX q0 = VecX::Constant(n, 0.2);
      for (bool constrained : {false, true}) {
        Model model = models::pendulum(n);
        for (int j = 0; j < n; ++j) model.add_actuator(j);
        if (constrained) model = constrained_pendulum(n, q0);
        const int m = model.n_constraints();
        ASSERT_EQ(m, constrained ? 2 : 0);
        HermiteSimpsonTranscription imp(model, N, 0.1, ControlMode::PerPoint, true);
        HermiteSimpsonTranscription ex(model, N, 0.1, ControlMode::PerPoint, false);
        EXPECT_EQ(imp.n_variables(), (8 * N + 4) * n + (2 * N + 1) * m);
        EXPECT_EQ(ex.n_variables(), (6 * N + 3) * n + (2 * N + 1) * m);
        EXPECT_EQ(imp.n_constraints(), (6 * N + 1) * n + (6 * N + 3) * m - 4 * N * m);
        EXPECT_EQ(ex.n_constraints(), 4 * N * n + (6 * N + 3) * m - 4 * N * m);
        // Offsets: q, v (a) at every point, then u, then λ.
        for (const auto* tr : {&imp, &ex}) {
          EXPECT_EQ(tr->n_points(), 2 * N + 1);
          EXPECT_EQ(tr->n_control_values(), 2 * N + 1);
          EXPECT_EQ(tr->q_offset(), 0);
          EXPECT_EQ(tr->v_offset(), (2 * N + 1) * n);
          EXPECT_EQ(tr->lambda_offset(), tr->u_offset() + (2 * N + 1) * n);
          EXPECT_EQ(tr->n_variables(), tr->lambda_offset() + (2 * N + 1) * m);
        }
        EXPECT_EQ(imp.a_offset(), 2 * (2 * N + 1) * n);
        EXPECT_EQ(imp.u_offset(), 3 * (2 * N + 1) * n);
        EXPECT_EQ(ex.a_offset(), -1);
        EXPECT_EQ(ex.u_offset(), 2 * (2 * N + 1) * n);
        // Held controls: one per interval.
        HermiteSimpsonTranscription held(model, N, 0.1, ControlMode::Held, true);
        EXPECT_EQ(held.n_control_values(), N);
        EXPECT_EQ(held.n_variables(), (6 * N + 3) * n + N * n + (2 * N + 1) * m);
        EXPECT_EQ(held.n_constraints(), imp.n_constraints());
      }
    }
  }
}

// (2) Exact Jacobian against central differences, both forms, both control modes.
TEST(HermiteSimpsonTranscription, JacobianMatchesFiniteDifferencesUnconstrained) {
  std::mt19937 rng(11);
  for (bool implicit : {true, false})
    for (ControlMode mode : {ControlMode::PerPoint, ControlMode::Held}) {
      check_jacobian(models::pendulum(3), 2, 0.05, mode, implicit, rng, "pendulum (no forces, no controls)");
      check_jacobian(forced_pendulum(), 2, 0.05, mode, implicit, rng, "forced pendulum");
      check_jacobian(forced_pendulum(), 1, 0.1, mode, implicit, rng, "forced pendulum");
      check_jacobian(forced_tree(), 3, 0.02, mode, implicit, rng, "forced tree");
    }
}

// Body wrench elements (drag, and a point force scaled by a control input) are supported through
// force_jacobians.
TEST(HermiteSimpsonTranscription, JacobianMatchesFiniteDifferencesWithBodyWrenches) {
  std::mt19937 rng(12);
  for (bool implicit : {true, false})
    for (ControlMode mode : {ControlMode::PerPoint, ControlMode::Held})
      check_jacobian(pendulum_with_wrenches(), 2, 0.05, mode, implicit, rng, "pendulum with wrenches");
}

// Constrained models: the constraint-acceleration rows' q-derivative contains a third derivative
// of h, which the transcription takes by central differences of the exact ∇²h v: still well inside
// the 1e-6 relative tolerance.
TEST(HermiteSimpsonTranscription, JacobianMatchesFiniteDifferencesConstrained) {
  std::mt19937 rng(13);
  const Model pend = constrained_pendulum(4, VecX::Constant(4, 0.2));
  const Model tree = constrained_tree();
  for (bool implicit : {true, false})
    for (ControlMode mode : {ControlMode::PerPoint, ControlMode::Held}) {
      check_jacobian(pend, 2, 0.05, mode, implicit, rng, "constrained pendulum");
      check_jacobian(tree, 2, 0.03, mode, implicit, rng, "constrained tree");
    }
}

// (3) The constraints vanish at the knot and midpoint values of converged steps of the baseline
// HS simulator (springs, dampers, actuators; per-point controls varying over the step, and a
// held control constant over it), both forms; N = 1, and N = 3 chained steps.
TEST(HermiteSimpsonTranscription, ConstraintsVanishAtBaselineSteps) {
  std::mt19937 rng(21);
  for (const Model& model : {forced_pendulum(), forced_tree()}) {
    const int n = model.n(), m = model.n_controls();
    for (ControlMode mode : {ControlMode::PerPoint, ControlMode::Held})
      for (int N : {1, 3}) {
        // Held controls and N > 1: the knot shared by intervals k-1 and k has one a in the
        // transcription, while the baseline's a there depends on the control used on each side;
        // HeldConstantControlRollout covers that case with one control on every interval.
        if (mode == ControlMode::Held && N > 1) continue;
        const double h = 0.03;
        HermiteSimpsonOptions opt;
        opt.tol = 1e-13;
        HermiteSimpson hs(model, h, opt);
        const int P = 2 * N + 1;
        MatX Q(n, P), V(n, P), A(n, P), U(m, P);
        // Controls: per point, random values shared at the knots; held, one per interval.
        for (int i = 0; i < P; ++i) U.col(i) = uniform(rng, m, -1, 1);
        VecX q = uniform(rng, n, -0.8, 0.8), v = uniform(rng, n, -1, 1);
        Q.col(0) = q;
        V.col(0) = v;
        for (int k = 0; k < N; ++k) {
          MatX u(m, 3);
          if (mode == ControlMode::PerPoint) u = U.middleCols(2 * k, 3);
          else u = U.col(k).replicate(1, 3);
          VecX q1(n), v1(n);
          const SolveInfo info = hs.step(q, v, u, q1, v1);
          ASSERT_TRUE(info.converged()) << to_string(info.status);
          if (k == 0) A.col(0) = hs.a_k();
          Q.col(2 * k + 1) = hs.q_mid();
          V.col(2 * k + 1) = hs.v_mid();
          A.col(2 * k + 1) = hs.a_mid();
          Q.col(2 * k + 2) = q1;
          V.col(2 * k + 2) = v1;
          A.col(2 * k + 2) = hs.a_next();
          q = q1;
          v = v1;
        }
        for (bool implicit : {true, false}) {
          SCOPED_TRACE(std::string(implicit ? "implicit" : "explicit") +
                       (mode == ControlMode::PerPoint ? " per-point" : " held") + " N " + std::to_string(N) +
                       " n " + std::to_string(n));
          HermiteSimpsonTranscription tr(model, N, h, mode, implicit);
          VecX x = VecX::Zero(tr.n_variables());
          x.segment(tr.q_offset(), P * n) = Q.reshaped();
          x.segment(tr.v_offset(), P * n) = V.reshaped();
          if (implicit) x.segment(tr.a_offset(), P * n) = A.reshaped();
          if (mode == ControlMode::PerPoint) x.segment(tr.u_offset(), P * m) = U.reshaped();
          else x.segment(tr.u_offset(), N * m) = U.leftCols(N).reshaped();
          VecX g(tr.n_constraints());
          tr.constraints(x, g);
          EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-9) << "largest |x| " << x.cwiseAbs().maxCoeff();
          // Not trivially satisfied: moving one midpoint configuration breaks it.
          x[tr.q_offset() + n] += 1e-3;
          tr.constraints(x, g);
          EXPECT_GT(g.cwiseAbs().maxCoeff(), 1e-4);
        }
      }
  }
}

// Held controls over several intervals with a constant control: the rolled-out trajectory
// satisfies the constraints of every form (the knot convention cannot matter then).
TEST(HermiteSimpsonTranscription, HeldConstantControlRollout) {
  std::mt19937 rng(22);
  const Model model = forced_pendulum();
  const int n = model.n(), m = model.n_controls(), N = 4, P = 2 * N + 1;
  const double h = 0.02;
  HermiteSimpsonOptions opt;
  opt.tol = 1e-13;
  HermiteSimpson hs(model, h, opt);
  const VecX uc = uniform(rng, m, -1, 1);
  const MatX u = uc.replicate(1, 3);
  MatX Q(n, P), V(n, P), A(n, P);
  VecX q = uniform(rng, n, -0.5, 0.5), v = uniform(rng, n, -1, 1);
  Q.col(0) = q;
  V.col(0) = v;
  for (int k = 0; k < N; ++k) {
    VecX q1(n), v1(n);
    ASSERT_TRUE(hs.step(q, v, u, q1, v1).converged());
    if (k == 0) A.col(0) = hs.a_k();
    Q.col(2 * k + 1) = hs.q_mid();
    V.col(2 * k + 1) = hs.v_mid();
    A.col(2 * k + 1) = hs.a_mid();
    Q.col(2 * k + 2) = q = q1;
    V.col(2 * k + 2) = v = v1;
    A.col(2 * k + 2) = hs.a_next();
  }
  for (bool implicit : {true, false}) {
    HermiteSimpsonTranscription tr(model, N, h, ControlMode::Held, implicit);
    VecX x(tr.n_variables());
    x.segment(tr.q_offset(), P * n) = Q.reshaped();
    x.segment(tr.v_offset(), P * n) = V.reshaped();
    if (implicit) x.segment(tr.a_offset(), P * n) = A.reshaped();
    x.segment(tr.u_offset(), N * m) = uc.replicate(N, 1);
    VecX g(tr.n_constraints());
    tr.constraints(x, g);
    EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-9) << (implicit ? "implicit" : "explicit");
  }
}

// constraints() and jacobian() from several threads at once give the serial results.
TEST(HermiteSimpsonTranscription, ConcurrentCallsAgree) {
  std::mt19937 rng(31);
  const Model model = constrained_tree();
  for (bool implicit : {true, false}) {
    HermiteSimpsonTranscription tr(model, 3, 0.03, ControlMode::PerPoint, implicit);
    std::vector<VecX> xs;
    for (int t = 0; t < 4; ++t) xs.push_back(random_x(tr, model, rng));
    std::vector<VecX> g_ref(4, VecX(tr.n_constraints())), j_ref(4, VecX(tr.structure().nnz()));
    for (int t = 0; t < 4; ++t) {
      tr.constraints(xs[t], g_ref[t]);
      tr.jacobian(xs[t], j_ref[t]);
    }
    std::vector<VecX> g(4, VecX(tr.n_constraints())), J(4, VecX(tr.structure().nnz()));
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
      threads.emplace_back([&, t] {
        for (int rep = 0; rep < 3; ++rep) {
          tr.constraints(xs[t], g[t]);
          tr.jacobian(xs[t], J[t]);
        }
      });
    for (auto& th : threads) th.join();
    for (int t = 0; t < 4; ++t) {
      EXPECT_EQ((g[t] - g_ref[t]).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ((J[t] - j_ref[t]).cwiseAbs().maxCoeff(), 0.0);
    }
  }
}
