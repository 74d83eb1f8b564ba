#include "hovi/trajopt/body_points.hpp"

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/constraints/constraint.hpp"
#include "hovi/errors.hpp"

namespace hovi {

void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX& J) {
  const int n = model.n(), P = static_cast<int>(Q.cols()), m = static_cast<int>(bodies.size());
  if (Q.rows() != n || points.rows() != 3 || points.cols() != m)
    throw InputError("body_point_kinematics: Q (n x P), bodies (m) and points (3 x m) do not match");
  std::vector<PointConstraint> point;  // h = world position of point i
  point.reserve(m);
  for (int i = 0; i < m; ++i) {
    point.emplace_back(bodies[i], points.col(i), Vec3::Zero());
    point.back().check(model);
  }
  X.resize(3, m * P);
  J.resize(3, n * m * P);
  for (int p = 0; p < P; ++p) {
    forward_kinematics(model, data, Q.col(p));
    const KinematicsView kin{model, data.g.data(), data.Sbar.data(), 1};
    for (int i = 0; i < m; ++i) {
      point[i].value(kin, Q.col(p), X.col(p * m + i));
      point[i].jacobian(kin, J.middleCols((p * m + i) * n, n));
    }
  }
}

}  // namespace hovi
