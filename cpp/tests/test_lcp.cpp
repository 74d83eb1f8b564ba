// LcpSolver (contact/lcp.hpp) against a brute-force enumeration of every complementary basis on
// small LCPs with a P-matrix (one solution), and the validity of its solutions of the
// Stewart-Trinkle LCPs of a contact step (not unique: friction splits); the guessed basis path.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "hovi/integrators/lcp.hpp"

using namespace hovi;

namespace {

// Every basis tried: the z of the (unique, for a P-matrix) solution.
VecX enumerate(const MatX& M, const VecX& b) {
  const int n = static_cast<int>(b.size());
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> B;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1) B.push_back(i);
    VecX z = VecX::Zero(n);
    if (!B.empty()) {
      MatX Mbb(B.size(), B.size());
      VecX rhs(B.size());
      for (std::size_t i = 0; i < B.size(); ++i) {
        rhs[i] = -b[B[i]];
        for (std::size_t j = 0; j < B.size(); ++j) Mbb(i, j) = M(B[i], B[j]);
      }
      const VecX zb = Mbb.fullPivLu().solve(rhs);
      for (std::size_t i = 0; i < B.size(); ++i) z[B[i]] = zb[i];
    }
    const VecX w = M * z + b;
    if (z.minCoeff() >= -1e-12 && w.minCoeff() >= -1e-12) return z;
  }
  return VecX();
}

void expect_solution(const MatX& M, const VecX& b, const VecX& z) {
  const VecX w = M * z + b;
  const double scale = 1 + b.cwiseAbs().maxCoeff() + z.cwiseAbs().maxCoeff();
  EXPECT_GE(z.minCoeff(), 0.0);
  EXPECT_GE(w.minCoeff(), -1e-11 * scale);
  EXPECT_LE(z.cwiseProduct(w).cwiseAbs().maxCoeff(), 1e-11 * scale * scale);
}

}  // namespace

TEST(Lcp, MatchesEnumerationOnPMatrices) {
  std::mt19937 rng(7);
  std::normal_distribution<double> N01;
  LcpSolver lcp;
  int with_pivots = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + trial % 8;
    MatX A(n, n), S(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) A(i, j) = N01(rng), S(i, j) = N01(rng);
    const MatX M = A * A.transpose() + 0.1 * MatX::Identity(n, n) + (S - S.transpose());  // positive definite: P
    VecX b(n);
    for (int i = 0; i < n; ++i) b[i] = N01(rng);
    VecX z;
    std::vector<char> basis;
    ASSERT_TRUE(lcp.solve(M, b, z, basis));
    const VecX ref = enumerate(M, b);
    ASSERT_EQ(ref.size(), n);
    EXPECT_LE((z - ref).cwiseAbs().maxCoeff(), 1e-10 * (1 + ref.cwiseAbs().maxCoeff())) << "trial " << trial;
    expect_solution(M, b, z);
    with_pivots += lcp.pivots() > 0;
    // The basis found serves as the next guess: no pivot, the same z.
    VecX z2;
    ASSERT_TRUE(lcp.solve(M, b, z2, basis));
    EXPECT_EQ(lcp.pivots(), 0);
    EXPECT_LE((z2 - z).cwiseAbs().maxCoeff(), 1e-12 * (1 + z.cwiseAbs().maxCoeff()));
  }
  EXPECT_GT(with_pivots, 100);  // Lemke ran (b >= 0 alone would need none)
}

TEST(Lcp, SolvesStewartTrinkleContactLcps) {
  // C contacts with d friction directions: z = (λ, β_1..d, γ) per contact, w = (Nλ row, Dβ rows,
  // cone row), as contact_solver.cpp builds them.
  std::mt19937 rng(11);
  std::normal_distribution<double> N01;
  LcpSolver lcp;
  for (int trial = 0; trial < 200; ++trial) {
    const int C = 1 + trial % 8, d = trial % 2 ? 4 : 2, pc = d + 2, nz = C * pc;
    const double mu = 0.1 + 0.2 * (trial % 5);
    // W = J M^{-1} J^T (M = 1) of k degrees of freedom (k < 3C: redundant contacts, as the eight
    // corners of a box), b from the predicted motion J v and the current heights (>= 0).
    const int k = trial % 3 == 0 ? 2 + trial % 5 : 3 * C;
    MatX J(3 * C, k);
    for (int i = 0; i < 3 * C; ++i)
      for (int j = 0; j < k; ++j) J(i, j) = N01(rng);
    const MatX W = J * J.transpose() / k;
    const VecX a = J * VecX::NullaryExpr(k, [&] { return N01(rng); }) / std::sqrt(double(k));
    MatX Dir(d, 3);
    Dir.setZero();
    Dir(0, 0) = 1, Dir(1, 0) = -1;
    if (d == 4) Dir(2, 1) = 1, Dir(3, 1) = -1;
    MatX E = MatX::Zero(3 * C, nz), S = MatX::Zero(nz, 3 * C);
    for (int c = 0; c < C; ++c) {
      E(3 * c + 2, c * pc) = 1;
      E.block(3 * c, c * pc + 1, 3, d) = Dir.transpose();
      S(c * pc, 3 * c + 2) = 1;
      S.block(c * pc + 1, 3 * c, d, 3) = Dir;
    }
    MatX M = S * W * E;
    VecX b = S * a;
    for (int c = 0; c < C; c += 3) b[c * pc] += std::abs(0.3 * N01(rng));
    for (int c = 0; c < C; ++c) {
      for (int i = 0; i < d; ++i) M(c * pc + 1 + i, c * pc + d + 1) += 1;
      M(c * pc + d + 1, c * pc) = mu;
      M.row(c * pc + d + 1).segment(c * pc + 1, d).setConstant(-1);
      b[c * pc + d + 1] = 0;
    }
    VecX z;
    std::vector<char> basis;
    ASSERT_TRUE(lcp.solve(M, b, z, basis)) << "trial " << trial;
    expect_solution(M, b, z);
  }
}

TEST(Lcp, ZeroSolvesANonNegativeRightHandSide) {
  LcpSolver lcp;
  VecX z;
  std::vector<char> basis{1, 1};
  ASSERT_TRUE(lcp.solve(MatX::Identity(2, 2), VecX::Constant(2, 0.5), z, basis));
  EXPECT_EQ(z, VecX::Zero(2));
  EXPECT_EQ(basis, (std::vector<char>{0, 0}));
}
