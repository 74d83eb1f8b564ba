// World positions of body points and their Jacobians at many configurations at once, for path
// constraints and costs on bodies (a foot above an obstacle, a hand at a target).
#pragma once
#include <vector>

#include "hovi/model/data.hpp"

namespace hovi {

// Q: n x K configurations; bodies[k] and points.col(k) (in the body's COM frame) give the point
// of sample k. X: 3 x K world positions; J: 3 x (n K), block k = dX_k/dq at Q.col(k).
void body_point_kinematics(const Model& model, Data& data, const Eigen::Ref<const MatX>& Q,
                           const std::vector<int>& bodies, const Eigen::Ref<const MatX>& points, MatX& X, MatX& J);

}  // namespace hovi
