// Model queries (model.hpp): the joints that move a set of bodies, against the kinematics (a joint
// moves a body iff changing its coordinate moves the body's frame).
#include <gtest/gtest.h>

#include "test_models.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/model/data.hpp"

using namespace hovi;

TEST(Model, JointsMovingAreTheOnesWhoseCoordinatesMoveTheBodies) {
  const Model m = test_models::branched_tree();   // a(0) -> b(1) -> c(2); a -> d(3) -> e(4), f(5)
  Data data(m);
  const VecX q0 = (VecX(6) << 0.3, -0.2, 0.5, 0.1, -0.4, 0.2).finished();
  forward_kinematics(m, data, q0);
  const std::vector<SE3> g0 = data.g;
  std::vector<std::vector<char>> moves(m.n(), std::vector<char>(m.n(), 0));   // moves[j][b]
  for (int j = 0; j < m.n(); ++j) {
    VecX q = q0;
    q[j] += 0.1;
    forward_kinematics(m, data, q);
    for (int b = 0; b < m.n(); ++b)
      moves[j][b] = (data.g[b].p - g0[b].p).norm() + (data.g[b].R - g0[b].R).norm() > 1e-12;
  }
  for (const std::vector<int>& bodies : std::vector<std::vector<int>>{{}, {0}, {2}, {4, 5}, {2, 4}, {5, 1}}) {
    std::vector<int> expected;
    for (int j = 0; j < m.n(); ++j) {
      bool any = false;
      for (int b : bodies) any = any || moves[j][b];
      if (any) expected.push_back(j);
    }
    EXPECT_EQ(m.joints_moving(bodies), expected);
  }
  EXPECT_EQ(m.joints_moving({2, 4}), (std::vector<int>{0, 1, 2, 3, 4}));   // the tree by hand
}
