// Fixed-size Eigen types used throughout hovi. Twists are (omega, v) and wrenches (tau, f),
// the paper's ordering (Sec. 2.2); Pinocchio orders them (linear, angular).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hovi {
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat4 = Eigen::Matrix4d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Twist = Vec6;   // element of T_e SE(3): (omega, v_O)
using Wrench = Vec6;  // element of T_e^* SE(3): (tau, f_O)
}  // namespace hovi
