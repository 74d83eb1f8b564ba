// box_qp (control/box_qp.hpp) against a brute-force enumeration of every active set (each component
// at its lower bound, its upper bound or free) on small random problems, and the free set it reports.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>
#include <random>

#include "hovi/control/box_qp.hpp"

using namespace hovi;

namespace {

// The minimiser by enumeration: for each assignment, solve the free part with the rest at its bound;
// keep the feasible one of least value (a strictly convex QP has one minimiser).
VecX enumerate(const MatX& H, const VecX& g, const VecX& lo, const VecX& hi) {
  const int m = int(g.size());
  int total = 1;
  for (int i = 0; i < m; ++i) total *= 3;
  double best = std::numeric_limits<double>::infinity();
  VecX xbest;
  for (int code = 0; code < total; ++code) {
    std::vector<int> fr;
    VecX x = VecX::Zero(m);
    int c = code;
    for (int i = 0; i < m; ++i, c /= 3) {
      if (c % 3 == 0) x[i] = lo[i];
      else if (c % 3 == 1) x[i] = hi[i];
      else fr.push_back(i);
    }
    if (!fr.empty()) {
      MatX Hf(fr.size(), fr.size());
      VecX rhs(fr.size());
      for (std::size_t i = 0; i < fr.size(); ++i) {
        rhs[i] = -g[fr[i]];
        for (int j = 0; j < m; ++j) {
          const auto it = std::find(fr.begin(), fr.end(), j);
          if (it == fr.end()) rhs[i] -= H(fr[i], j) * x[j];
          else Hf(i, it - fr.begin()) = H(fr[i], j);
        }
      }
      const VecX xf = Hf.llt().solve(rhs);
      for (std::size_t i = 0; i < fr.size(); ++i) x[fr[i]] = xf[i];
    }
    if ((x.array() < lo.array() - 1e-12).any() || (x.array() > hi.array() + 1e-12).any()) continue;
    const double v = 0.5 * x.dot(H * x) + g.dot(x);
    if (v < best) {
      best = v;
      xbest = x;
    }
  }
  return xbest;
}

}  // namespace

TEST(BoxQp, MatchesEnumeration) {
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int m = 1 + trial % 5;
    MatX L(m, m);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) L(i, j) = N(rng);
    const MatX H = L * L.transpose() + 0.1 * MatX::Identity(m, m);
    VecX g(m), lo(m), hi(m), x0 = VecX::Zero(m);
    for (int i = 0; i < m; ++i) {
      g[i] = 3 * N(rng);
      lo[i] = -std::abs(N(rng));
      hi[i] = std::abs(N(rng));
      x0[i] = N(rng);
    }
    const BoxQpResult r = box_qp(H, g, lo, hi, x0);
    ASSERT_TRUE(r.ok);
    const VecX x = enumerate(H, g, lo, hi);
    EXPECT_LT((r.x - x).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    const VecX grad = g + H * r.x;
    for (int i = 0; i < m; ++i) {  // KKT: free components stationary, clamped ones pushed outwards
      if (r.free[i]) EXPECT_LT(std::abs(grad[i]), 1e-8) << trial;
      else EXPECT_TRUE((r.x[i] <= lo[i] && grad[i] > 0) || (r.x[i] >= hi[i] && grad[i] < 0)) << trial;
    }
  }
}

TEST(BoxQp, UnboundedIsTheNewtonStep) {
  const MatX H = (MatX(2, 2) << 2, 0.5, 0.5, 1).finished();
  const VecX g = (VecX(2) << 1, -1).finished();
  const VecX inf = VecX::Constant(2, std::numeric_limits<double>::infinity());
  const BoxQpResult r = box_qp(H, g, -inf, inf, VecX::Zero(2));
  EXPECT_LT((r.x + H.llt().solve(g)).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_TRUE(r.free.all());
}
