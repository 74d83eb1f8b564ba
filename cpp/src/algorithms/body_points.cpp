#include "hovi/algorithms/body_points.hpp"

#include <string>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

void body_point_jacobian(const KinematicsView& kin, int body, const Vec3& r, Vec3& x, Eigen::Ref<MatX> J) {
  x = kin.pose(body).act(r);  // x = g_b r
  // dx/dq_j = v_j + ω_j × x for S̄_j = (ω_j, v_j), j on the path from b to the root.
  for (int j = body; j >= 0; j = kin.model.parent[j]) {
    const Twist& S = kin.twist(j);
    J.col(j) = S.tail<3>() + S.head<3>().cross(x);
  }
}

void body_point_force_derivative(const KinematicsView& kin, int body, const Vec3& r, const Vec3& F, Eigen::Ref<MatX> H) {
  const Vec3 x = kin.pose(body).act(r);
  for (int j = body; j >= 0; j = kin.model.parent[j]) {
    const Twist& Sj = kin.twist(j);
    const Vec3 wj = Sj.head<3>(), vj = Sj.tail<3>();
    for (int k = body; k >= 0; k = kin.model.parent[k]) {
      const Twist& Sk = kin.twist(k);
      const Vec3 wk = Sk.head<3>(), vk = Sk.tail<3>();
      const Vec3 Jk = vk + wk.cross(x);  // dx/dq_k
      double d = F.dot(wj.cross(Jk));
      if (k < j) {  // both on one path to the root: k is a strict ancestor of j
        const Vec3 dw = wk.cross(wj), dv = wk.cross(vj) + vk.cross(wj);
        d += F.dot(dv + dw.cross(x));
      }
      H(j, k) += d;
    }
  }
}

void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX* J) {
  const int n = model.n(), P = static_cast<int>(Q.cols()), m = static_cast<int>(bodies.size());
  if (Q.rows() != n || points.rows() != 3 || points.cols() != m)
    throw InputError("body_point_kinematics: Q (n x P), bodies (m) and points (3 x m) do not match");
  for (int b : bodies)
    if (b < 0 || b >= n) throw ModelError("body_point_kinematics: body index " + std::to_string(b) + " out of range");
  X.resize(3, m * P);
  if (J) J->setZero(3, n * m * P);
  const KinematicsView kin{model, data.g.data(), data.Sbar.data(), 1};
  for (int p = 0; p < P; ++p) {
    forward_kinematics(model, data, Q.col(p));
    for (int i = 0; i < m; ++i) {
      if (!J) {
        X.col(p * m + i) = kin.pose(bodies[i]).act(Vec3(points.col(i)));
        continue;
      }
      Vec3 x;
      body_point_jacobian(kin, bodies[i], points.col(i), x, J->middleCols((p * m + i) * n, n));
      X.col(p * m + i) = x;
    }
  }
}

}  // namespace hovi
