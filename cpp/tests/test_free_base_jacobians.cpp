// A free base's step linearised in tangent coordinates (integrators/free_base_jacobians.hpp): A and B of
// the floating chain, with its arm actuated, against central differences of whole steps (rollouts of
// one step) taken through FreeBase::integrate and FreeBase::difference, at s = 1, 2, 3.
#include <gtest/gtest.h>

#include <cstdio>

#include "hovi/algorithms/free_base.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/integrators/linearizer.hpp"
#include "test_models.hpp"

using namespace hovi;

namespace {

// (q^{k+1} ⊖ q_ref, p^{k+1} - p_ref) of one step from (q, p) with controls u (m x (s+1)).
VecX tangent_end(const GalerkinIntegrator& integ, const FreeBase& base, const VecX& q, const VecX& p, const MatX& u,
                 const VecX& q_ref, const VecX& p_ref) {
  const int n = integ.model().n(), S1 = integ.quadrature().s + 1, m = integ.model().n_controls();
  MatX U(1, S1 * m);
  for (int a = 0; a < S1; ++a) U.block(0, a * m, 1, m) = u.col(a).transpose();
  const Rollout r = integ.rollout(q, p, 1, U);
  EXPECT_EQ(r.steps, 1);
  VecX out(2 * n);
  out << base.difference(q_ref, r.q.row(1).transpose()), r.p.row(1).transpose() - p_ref;
  return out;
}

}  // namespace

TEST(FreeBaseJacobians, AreTheStepsDifferencesThroughIntegrateAndDifference) {
  for (int s = 1; s <= 3; ++s) {
    Model model = test_models::floating_chain(true);
    model.add_actuator(6, 1.5);
    const GalerkinIntegrator integ(model, s, 0.02);
    const FreeBase base(model);
    const int n = model.n(), S1 = s + 1;
    VecX q(8), v(7);
    q << 0.1, -0.2, 0.3, 0.2, -0.1, 0.3, 0.927, 0.4;
    q.segment<4>(3).normalize();
    v << 0.3, -0.1, 0.2, -1.0, 2.0, 0.5, 0.7;
    const VecX p = integ.momentum(q, v);
    const MatX u = VecX::LinSpaced(S1, 0.3, -0.4).transpose();
    const Rollout nominal = integ.rollout(q, p, 1, Eigen::Map<const MatX>(u.data(), 1, S1));
    const MatX qc = Eigen::Map<const MatX>(nominal.control_points.row(0).data(), n, S1);
    MatX A, B;
    ASSERT_TRUE(Linearizer(integ).step_jacobians(qc, u, &A, &B, MatX(), nullptr, nullptr, 0, q));
    const VecX q1 = nominal.q.row(1).transpose(), p1 = nominal.p.row(1).transpose();
    const double h = 1e-5;
    MatX Ad(2 * n, 2 * n), Bd(2 * n, S1);
    for (int i = 0; i < 2 * n; ++i) {
      VecX e = VecX::Zero(2 * n);
      e[i] = h;
      Ad.col(i) = (tangent_end(integ, base, base.integrate(q, e.head(n)), p + e.tail(n), u, q1, p1) -
                   tangent_end(integ, base, base.integrate(q, -e.head(n)), p - e.tail(n), u, q1, p1)) / (2 * h);
    }
    for (int a = 0; a < S1; ++a) {
      MatX up = u, um = u;
      up(0, a) += h;
      um(0, a) -= h;
      Bd.col(a) = (tangent_end(integ, base, q, p, up, q1, p1) - tangent_end(integ, base, q, p, um, q1, p1)) / (2 * h);
    }
    const double ea = (A - Ad).cwiseAbs().maxCoeff() / Ad.cwiseAbs().maxCoeff();
    const double eb = (B - Bd).cwiseAbs().maxCoeff() / Bd.cwiseAbs().maxCoeff();
    std::printf("s = %d: A within %.1e, B within %.1e of the differences\n", s, ea, eb);
    EXPECT_LT(ea, 1e-7) << "s = " << s;
    EXPECT_LT(eb, 1e-6) << "s = " << s;
  }
}
