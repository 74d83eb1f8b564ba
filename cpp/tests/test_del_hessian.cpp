// del_hessian (algorithms/del_hessian.hpp): the second derivatives of nu . (one step's DEL rows)
// against central differences of the exact Jacobian's nu^T Jq and nu^T Ju (del_jacobian.hpp), for
// s = 1, 2, 3, on a branched tree without forces, and on the forced pendulum with body wrenches
// (world point forces, exact, one on a control; a body-frame follower force on a control, a world
// force with a torque on another, drag: differenced), with the wrenches free of q̇ (no drag: the q̇
// columns are not differenced), and with the world point forces alone. Measured: 2.5e-11 to 1.9e-10
// relative (the central differences' own noise).
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "test_models.hpp"
#include "hovi/algorithms/del_hessian.hpp"
#include "hovi/forces/builtin_wrenches.hpp"

using namespace hovi;

namespace {

// World point forces without torque (exact: BodyWrench::world_point_force), one on a control and
// one constant; with `others`, a body-frame follower force and a world force with a torque on
// controls (differenced) and, with `drag`, drag.
Model with_wrenches(bool drag, bool others = true) {
  Model m = test_models::forced_pendulum();
  const int contact = m.add_control();
  m.add_wrench(std::make_shared<PointWrench>(4, Vec3(0.05, -0.1, 0.2), Vec3(0.4, 0.1, -0.3), Vec3::Zero(),
                                             PointWrench::Frame::World, contact));
  m.add_wrench(std::make_shared<PointWrench>(3, Vec3(-0.1, 0.0, 0.1), Vec3(0.0, 0.2, 0.6), Vec3::Zero(),
                                             PointWrench::Frame::World));
  if (others) {
    const int follower = m.add_control(), world = m.add_control();
    m.add_wrench(std::make_shared<PointWrench>(4, Vec3(0.1, 0.05, -0.2), Vec3(0.3, -0.2, 1.0), Vec3::Zero(),
                                               PointWrench::Frame::Body, follower));
    m.add_wrench(std::make_shared<PointWrench>(2, Vec3(0.0, 0.1, -0.3), Vec3(0.0, 0.5, -0.4), Vec3(0.2, 0.0, 0.1),
                                               PointWrench::Frame::World, world));
  }
  if (drag) m.add_wrench(std::make_shared<BodyDrag>(3, 0.7, 0.3));
  return m;
}

// max |H - central differences of the gradient (Jq^T nu, Ju^T nu)| / max |H| over Hqq, Huq, Huu.
double relative_error(const Model& model, int s) {
  const Quadrature quad(s);
  const int n = model.n(), m = model.n_controls(), S1 = s + 1;
  std::mt19937 rng(7 + s);
  const double dt = 0.05;
  MatX qc(n, S1), u(m, S1), nu(n, S1);
  for (int a = 0; a < S1; ++a) {
    qc.col(a) = test_models::uniform(rng, n, -0.6, 0.6);
    if (m) u.col(a) = test_models::uniform(rng, m, -2.0, 2.0);
    nu.col(a) = test_models::uniform(rng, n, -1.0, 1.0);
  }
  DelHessianWorkspace hws(model, quad);
  MatX Hqq(S1 * n, S1 * n), Huq(S1 * m, S1 * n), Huu(S1 * m, S1 * m);
  del_hessian(model, quad, hws, qc, u, nu, dt, Hqq, Huq, Huu);

  DelJacobianWorkspace jws(model, quad);
  MatX Jq(S1 * n, S1 * n), Ju;
  const Eigen::Map<const VecX> nu_flat(nu.data(), S1 * n);
  // the gradient of nu . rows with respect to (qc, u), both flattened column by column
  const auto gradient = [&](const MatX& q, const MatX& uu) {
    del_jacobian(model, quad, jws, q, uu, dt, Jq, m ? &Ju : nullptr);
    VecX g(S1 * (n + m));
    g.head(S1 * n) = Jq.transpose() * nu_flat;
    if (m) g.tail(S1 * m) = Ju.transpose() * nu_flat;
    return g;
  };
  MatX D(S1 * (n + m), S1 * (n + m));
  for (int j = 0; j < S1 * (n + m); ++j) {
    MatX qp = qc, qm = qc, up = u, um = u;
    const double h = 1e-5;
    if (j < S1 * n) {
      qp.data()[j] += h;
      qm.data()[j] -= h;
    } else {
      up.data()[j - S1 * n] += h;
      um.data()[j - S1 * n] -= h;
    }
    D.col(j) = (gradient(qp, up) - gradient(qm, um)) / (2 * h);
  }
  MatX H(S1 * (n + m), S1 * (n + m));
  H << Hqq, Huq.transpose(), Huq, Huu;
  return (H - D).cwiseAbs().maxCoeff() / H.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(DelHessian, BranchedTreeWithoutForces) {
  for (int s = 1; s <= 3; ++s) EXPECT_LT(relative_error(test_models::branched_tree(), s), 1e-8) << "s = " << s;
}

TEST(DelHessian, BodyWrenchesOnControlsAndDrag) {
  for (int s = 1; s <= 3; ++s) EXPECT_LT(relative_error(with_wrenches(true), s), 1e-8) << "s = " << s;
}

TEST(DelHessian, WrenchesFreeOfTheVelocity) {
  for (int s = 1; s <= 3; ++s) EXPECT_LT(relative_error(with_wrenches(false), s), 1e-8) << "s = " << s;
}

TEST(DelHessian, WorldPointForcesAlone) {
  const Model model = with_wrenches(false, false);
  EXPECT_TRUE(DelHessianWorkspace(model, Quadrature(1)).differenced.wrenches.empty());
  for (int s = 1; s <= 3; ++s) EXPECT_LT(relative_error(model, s), 1e-8) << "s = " << s;
}

TEST(DelHessian, ZeroMultipliersGiveZero) {
  const Model model = with_wrenches(true);
  const Quadrature quad(2);
  const int n = model.n(), m = model.n_controls();
  DelHessianWorkspace ws(model, quad);
  MatX Hqq(3 * n, 3 * n), Huq(3 * m, 3 * n), Huu(3 * m, 3 * m);
  del_hessian(model, quad, ws, MatX::Constant(n, 3, 0.3), MatX::Ones(m, 3), MatX::Zero(n, 3), 0.05, Hqq, Huq, Huu);
  EXPECT_EQ(Hqq.cwiseAbs().maxCoeff() + Huq.cwiseAbs().maxCoeff() + Huu.cwiseAbs().maxCoeff(), 0.0);
}
