// Lobatto quadrature: weights exact on polynomials of degree 2s-1, differentiation exact on
// degree s, for s = 1..8; the trapezoidal and Simpson special cases.
#include <gtest/gtest.h>

#include <cmath>

#include "hovi/errors.hpp"
#include "hovi/quadrature/lobatto.hpp"

using namespace hovi;

class LobattoOrder : public ::testing::TestWithParam<int> {};

TEST_P(LobattoOrder, WeightsIntegratePolynomialsOfDegree2sMinus1) {
  const int s = GetParam();
  const Quadrature Q(s);
  EXPECT_EQ(Q.c[0], 0.0);
  EXPECT_EQ(Q.c[s], 1.0);
  for (int k = 1; k <= s; ++k) EXPECT_GT(Q.c[k], Q.c[k - 1]);
  for (int deg = 0; deg <= 2 * s - 1; ++deg) {
    double sum = 0;
    for (int a = 0; a <= s; ++a) sum += Q.w[a] * std::pow(Q.c[a], deg);
    EXPECT_NEAR(sum, 1.0 / (deg + 1), 1e-13) << "degree " << deg;
  }
  // ... and not of degree 2s (so the rule is exactly Lobatto's, not a higher one)
  double sum = 0;
  for (int a = 0; a <= s; ++a) sum += Q.w[a] * std::pow(Q.c[a], 2 * s);
  EXPECT_GT(std::abs(sum - 1.0 / (2 * s + 1)), 1e-11);  // far above the 1e-13 round-off
}

TEST_P(LobattoOrder, DifferentiationMatrixIsExactOnDegreeS) {
  const int s = GetParam();
  const Quadrature Q(s);
  for (int deg = 0; deg <= s; ++deg)
    for (int a = 0; a <= s; ++a) {
      double d = 0;
      for (int b = 0; b <= s; ++b) d += Q.b(a, b) * std::pow(Q.c[b], deg);
      const double exact = deg == 0 ? 0.0 : deg * std::pow(Q.c[a], deg - 1);
      EXPECT_NEAR(d, exact, 1e-10 * std::pow(s, 2)) << "degree " << deg << " at node " << a;
    }
  for (int a = 0; a <= s; ++a)
    for (int b = 0; b <= s; ++b) EXPECT_NEAR(Q.a(a, b), Q.w[b] * Q.b(b, a), 1e-15);  // a^{ab} = w^b b^{ba}
  // The Lagrange basis interpolates.
  for (int a = 0; a <= s; ++a) EXPECT_LT((Q.basis(Q.c[a]) - VecX::Unit(s + 1, a)).norm(), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(S1to8, LobattoOrder, ::testing::Range(1, 9));

TEST(Lobatto, TrapezoidalAndSimpson) {
  const Quadrature T(1), S(2);
  EXPECT_NEAR(T.w[0], 0.5, 1e-15);
  EXPECT_NEAR(T.b(0, 0), -1, 1e-15);
  EXPECT_NEAR(T.b(1, 1), 1, 1e-15);
  EXPECT_NEAR(S.c[1], 0.5, 1e-15);
  EXPECT_NEAR(S.w[1], 4.0 / 6, 1e-15);
  // q̇^0 = (4 q^1 - 3 q^0 - q^2)/dt, q̇^1 = (q^2 - q^0)/dt (paper Example 2)
  EXPECT_NEAR(S.b(0, 0), -3, 1e-13);
  EXPECT_NEAR(S.b(0, 1), 4, 1e-13);
  EXPECT_NEAR(S.b(0, 2), -1, 1e-13);
  EXPECT_NEAR(S.b(1, 0), -1, 1e-13);
  EXPECT_NEAR(S.b(1, 1), 0, 1e-13);
}

TEST(Lobatto, RejectsBadS) {
  EXPECT_THROW(Quadrature(0), InputError);
  EXPECT_THROW(Quadrature(17), InputError);
}

// basis_derivative: the differentiation matrix at the nodes, and central differences of basis between them.
TEST_P(LobattoOrder, BasisDerivativeMatchesDifferentiationMatrixAndDifferences) {
  const int s = GetParam();
  const Quadrature Q(s);
  for (int a = 0; a <= s; ++a)
    EXPECT_LT((Q.basis_derivative(Q.c[a]).transpose() - Q.b.row(a)).cwiseAbs().maxCoeff(), 1e-10 * std::pow(s, 2));
  const double h = 1e-6;
  for (double x : {-0.2, 0.13, 0.5, 0.77, 1.1}) {
    const VecX fd = (Q.basis(x + h) - Q.basis(x - h)) / (2 * h);
    EXPECT_LT((Q.basis_derivative(x) - fd).cwiseAbs().maxCoeff(), 1e-6 * std::pow(s, 2)) << "x " << x;
  }
}

