// discrete_are and backward_riccati (control/riccati.hpp) against a scalar closed form, the DARE's own
// residual on random systems, and the finite horizon converging to the infinite one.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "hovi/control/riccati.hpp"
#include "hovi/errors.hpp"

using namespace hovi;

namespace {

MatX random_matrix(std::mt19937& rng, int r, int c) {
  std::normal_distribution<double> N(0, 1);
  MatX M(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) M(i, j) = N(rng);
  return M;
}

MatX dare_residual(const MatX& A, const MatX& B, const MatX& Q, const MatX& R, const MatX& P) {
  const MatX S = R + B.transpose() * P * B;
  return Q + A.transpose() * P * A - A.transpose() * P * B * S.ldlt().solve(B.transpose() * P * A) - P;
}

}  // namespace

TEST(Riccati, ScalarClosedForm) {
  // b^2 P^2 + (r (1 - a^2) - q b^2) P - q r = 0, the positive root
  const double a = 1.2, b = 0.5, q = 2.0, r = 0.3;
  const double c = r * (1 - a * a) - q * b * b;
  const double P_exact = (-c + std::sqrt(c * c + 4 * b * b * q * r)) / (2 * b * b);
  MatX P, K;
  discrete_are(MatX::Constant(1, 1, a), MatX::Constant(1, 1, b), MatX::Constant(1, 1, q), MatX::Constant(1, 1, r), P, K);
  EXPECT_NEAR(P(0, 0), P_exact, 1e-13 * P_exact);
  EXPECT_NEAR(K(0, 0), b * P_exact * a / (r + b * b * P_exact), 1e-13);
  EXPECT_LT(std::abs(a - b * K(0, 0)), 1.0);
}

TEST(Riccati, RandomSystemsSolveTheEquation) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 2 + trial % 6, m = 1 + trial % 3;
    const MatX A = random_matrix(rng, n, n), B = random_matrix(rng, n, m);
    const MatX L = random_matrix(rng, n, n);
    const MatX Q = L * L.transpose() + MatX::Identity(n, n), R = MatX::Identity(m, m) * (0.1 + trial);
    MatX P, K;
    int it = 0;
    discrete_are(A, B, Q, R, P, K, &it);
    EXPECT_LT(dare_residual(A, B, Q, R, P).cwiseAbs().maxCoeff(), 1e-10 * P.cwiseAbs().maxCoeff()) << trial;
    EXPECT_LT((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-12 * P.cwiseAbs().maxCoeff());
    const Eigen::EigenSolver<MatX> es(A - B * K);
    EXPECT_LT(es.eigenvalues().cwiseAbs().maxCoeff(), 1.0) << trial;  // stabilising
    EXPECT_LT(it, 30);
  }
}

TEST(Riccati, NotStabilisableIsAnError) {
  MatX P, K;
  EXPECT_THROW(discrete_are(MatX::Identity(2, 2) * 2, MatX::Zero(2, 1), MatX::Identity(2, 2), MatX::Identity(1, 1), P, K),
               InputError);
  EXPECT_THROW(discrete_are(MatX::Identity(2, 2), MatX::Ones(2, 1), MatX::Identity(2, 2), -MatX::Identity(1, 1), P, K),
               InputError);
}

TEST(Riccati, LongHorizonApproachesTheStationarySolution) {
  std::mt19937 rng(3);
  const int n = 4, m = 2, N = 400;
  const MatX A = random_matrix(rng, n, n) * 0.5, B = random_matrix(rng, n, m);
  const MatX Q = MatX::Identity(n, n), R = MatX::Identity(m, m);
  MatX P, K;
  discrete_are(A, B, Q, R, P, K);
  std::vector<MatX> Ks, Ps;
  backward_riccati(std::vector<MatX>(N, A), std::vector<MatX>(N, B), {Q}, {R}, MatX::Zero(n, n), Ks, Ps);
  ASSERT_EQ(Ks.size(), std::size_t(N));
  ASSERT_EQ(Ps.size(), std::size_t(N + 1));
  EXPECT_LT((Ps[0] - P).cwiseAbs().maxCoeff(), 1e-10 * P.cwiseAbs().maxCoeff());
  EXPECT_LT((Ks[0] - K).cwiseAbs().maxCoeff(), 1e-10 * K.cwiseAbs().maxCoeff());
  // one stage by hand: P^{N-1} = Q + K^T R K + (A - B K)^T QN (A - B K) with QN = 0, K = 0
  EXPECT_LT((Ps[N - 1] - Q).cwiseAbs().maxCoeff(), 1e-14);
}
