#include "hovi/trajopt/body_points.hpp"

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/constraints/constraint.hpp"
#include "hovi/errors.hpp"

namespace hovi {

void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX& J) {
  const int n = model.n(), K = static_cast<int>(Q.cols());
  if (Q.rows() != n || static_cast<int>(bodies.size()) != K || points.rows() != 3 || points.cols() != K)
    throw InputError("body_point_kinematics: Q (n x K), bodies (K) and points (3 x K) do not match");
  X.resize(3, K);
  J.resize(3, n * K);
  for (int k = 0; k < K; ++k) {
    const PointConstraint point(bodies[k], points.col(k), Vec3::Zero());  // h = world position
    point.check(model);
    forward_kinematics(model, data, Q.col(k));
    const KinematicsView kin{model, data.g.data(), data.Sbar.data(), 1};
    point.value(kin, Q.col(k), X.col(k));
    point.jacobian(kin, J.middleCols(k * n, n));
  }
}

}  // namespace hovi
