// World positions of body points and their Jacobians at many configurations at once, for path
// constraints, contact rows and costs on bodies (a foot above an obstacle, a hand at a target).
#pragma once
#include <vector>

#include "hovi/model/constraint.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

// Q: n x P configurations; bodies[i] and points.col(i) (in the body's COM frame) give point i of
// m. One forward kinematics per configuration serves all m points. X: 3 x (m P), column p m + i
// the world position of point i at Q.col(p); J: 3 x (n m P), block p m + i its dX/dq.
void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX& J);

// The world position x of the point r (in the COM frame of `body`) at the kinematics `kin` and its
// Jacobian dx/dq into J (3 x n; only the columns of the joints from `body` to the root are written).
void body_point_jacobian(const KinematicsView& kin, int body, const Vec3& r, Vec3& x, Eigen::Ref<MatX> J);

}  // namespace hovi
