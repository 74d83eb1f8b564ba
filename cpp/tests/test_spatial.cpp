// Spatial algebra against its defining identities (paper Sec. 2.2) and matrix exponentials.
#include <gtest/gtest.h>

#include <unsupported/Eigen/MatrixFunctions>

#include "hovi/spatial/algebra.hpp"

using namespace hovi;

namespace {
Mat4 hat4(const Twist& v) {
  Mat4 m = Mat4::Zero();
  m.topLeftCorner<3, 3>() = hat(v.head<3>());
  m.topRightCorner<3, 1>() = v.tail<3>();
  return m;
}
Twist vee4(const Mat4& m) {
  Twist v;
  v << m(2, 1), m(0, 2), m(1, 0), m.topRightCorner<3, 1>();
  return v;
}
SE3 random_se3() {
  const Twist xi = Twist::Random() * 2;
  return exp_twist(xi, 1.0);
}
}  // namespace

TEST(Spatial, ExpTwistMatchesMatrixExponential) {
  for (int k = 0; k < 20; ++k) {
    Twist S = Twist::Random();
    if (k % 5 == 0) S.head<3>().setZero();  // prismatic
    const double q = 3 * Eigen::internal::random<double>();
    const Mat4 expected = (hat4(S) * q).exp();
    EXPECT_LT((exp_twist(S, q).matrix() - expected).norm(), 1e-12);
  }
}

TEST(Spatial, GroupOperations) {
  const SE3 a = random_se3(), b = random_se3();
  EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).norm(), 1e-13);
  EXPECT_LT((a.inverse().matrix() - a.matrix().inverse()).norm(), 1e-12);
}

TEST(Spatial, AdjointMatchesConjugation) {
  for (int k = 0; k < 10; ++k) {
    const SE3 g = random_se3();
    const Twist v = Twist::Random();
    const Twist expected = vee4(g.matrix() * hat4(v) * g.matrix().inverse());
    EXPECT_LT((Ad(g) * v - expected).norm(), 1e-12);
    EXPECT_LT((Ad(g, v) - expected).norm(), 1e-12);
    const Wrench F = Wrench::Random();
    EXPECT_LT((AdInvT(g, F) - Ad(g).inverse().transpose() * F).norm(), 1e-12);
  }
}

TEST(Spatial, SmallAdjointIsLieBracket) {
  const Twist v1 = Twist::Random(), v2 = Twist::Random();
  const Twist expected = vee4(hat4(v1) * hat4(v2) - hat4(v2) * hat4(v1));
  EXPECT_LT((ad(v1) * v2 - expected).norm(), 1e-13);
  EXPECT_LT((ad(v1, v2) - expected).norm(), 1e-13);
}

TEST(Spatial, CoadjointIdentities) {
  const Twist v1 = Twist::Random(), v2 = Twist::Random();
  const Wrench F = Wrench::Random();
  // F^T ad_{v1} v2 = v2^T ad^D_F v1 = -v1^T ad^D_F v2
  const double a = F.dot(ad(v1) * v2), b = v2.dot(adD(F) * v1), c = -v1.dot(adD(F) * v2);
  EXPECT_NEAR(a, b, 1e-13);
  EXPECT_NEAR(a, c, 1e-13);
  EXPECT_LT((adD(F) + adD(F).transpose()).norm(), 1e-15);  // skew-symmetric (docs/paper.md C-7)
  EXPECT_LT((adT(v1, F) - ad(v1).transpose() * F).norm(), 1e-13);
  EXPECT_LT((adD(F) * v1 - ad(v1).transpose() * F).norm(), 1e-13);
}

TEST(Spatial, InertiaTransform) {
  Mat3 A = Mat3::Random();
  const Mat3 Ic = A * A.transpose() + Mat3::Identity();
  const SpatialInertia M = SpatialInertia::AtCom(2.5, Ic);
  const SE3 g = random_se3();
  const Mat6 Ainv = Ad(g).inverse();
  const Mat6 expected = Ainv.transpose() * M.matrix() * Ainv;
  EXPECT_LT((M.transformed(g).matrix() - expected).norm(), 1e-11);
  // Transforming twice composes.
  const SE3 h = random_se3();
  EXPECT_LT((M.transformed(g).transformed(h).matrix() - M.transformed(h * g).matrix()).norm(), 1e-10);
  const Twist v = Twist::Random();
  EXPECT_LT((M.transformed(g) * v - expected * v).norm(), 1e-11);
}
