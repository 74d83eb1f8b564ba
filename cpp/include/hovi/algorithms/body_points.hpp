// World positions of body points and their Jacobians at many configurations at once, for path
// constraints, contact rows and costs on bodies (a foot above an obstacle, a hand at a target).
#pragma once
#include <vector>

#include "hovi/model/constraint.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

// Scratch of the body-point evaluations at many configurations (trajopt's row blocks): the
// model's workspace, positions X and Jacobians J.
struct BodyPointWorkspace {
  explicit BodyPointWorkspace(const Model& model) : data(model) {}
  Data data;
  MatX X, J;
};

// Q: n x P configurations; bodies[i] and points.col(i) (in the body's COM frame) give point i of
// m. One forward kinematics per configuration serves all m points. X: 3 x (m P), column p m + i
// the world position of point i at Q.col(p); J (nullptr: positions only): 3 x (n m P), block p m + i
// its dX/dq. On return `data` holds the kinematics of the last configuration.
void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX* J);

// The world position x of the point r (in the COM frame of `body`) at the kinematics `kin` and its
// Jacobian dx/dq into J (3 x n; only the columns of the joints from `body` to the root are written).
void body_point_jacobian(const KinematicsView& kin, int body, const Vec3& r, Vec3& x, Eigen::Ref<MatX> J);

// H += d(J(q)^T F)/dq for a constant world force F at that point (n x n): with S̄_j = (ω_j, v_j) and
// J_j = v_j + ω_j × x, d(F . J_j)/dq_k = F . (dv_j + dω_j × x + ω_j × J_k) over the joints j, k from
// `body` to the root, where (dω_j, dv_j) = [S̄_k, S̄_j] for k a strict ancestor of j and 0 otherwise.
void body_point_force_derivative(const KinematicsView& kin, int body, const Vec3& r, const Vec3& F, Eigen::Ref<MatX> H);

}  // namespace hovi
