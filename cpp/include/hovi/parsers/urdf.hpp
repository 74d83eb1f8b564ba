// URDF -> Model through urdfdom.
//  - revolute, continuous (revolute without limits) and prismatic joints become bodies;
//  - fixed joints are merged: the child's inertia is lumped into the parent body and its
//    children re-attached with the composed placement;
//  - floating and planar joints (and the base, on request) are expanded into chains of 1-DoF
//    joints: floating = prismatic x, y, z then revolute z, y, x (Z-Y-X Euler angles, singular
//    at pitch = ±pi/2); planar with normal n = prismatic t1, prismatic t2 = t1 x n, revolute n,
//    with t1 the first of x, y, z not parallel to n (the x-z plane for n = y);
//  - mimic joints, limits and <dynamics> are kept as metadata;
//  - every number attribute urdfdom reads (origins, axes, inertials, limits, geometry, colours, ...)
//    must hold finite numbers, as many as it takes: checked before urdfdom, which silently zeroes
//    or drops some bad ones (a bad <inertial> would leave its link with zero mass or inertia).
// Errors raise UrdfError naming the link or joint at fault.
#pragma once
#include <string>
#include <vector>

#include "hovi/model/model.hpp"

namespace hovi {

// Floating: the free joint (Model::set_rotation_chart: its attitude on SO(3), a quaternion in the
// public configuration); Euler: the same six joints with yaw, pitch, roll as coordinates (singular
// at pitch ±90°), as the paper's robots.
enum class BaseJoint { Fixed, Floating, Euler, Planar };

struct UrdfOptions {
  BaseJoint base = BaseJoint::Fixed;  // how the root link is attached to the world
  Vec3 planar_normal = Vec3::UnitY(); // plane normal of a planar base (x-z plane by default)
  bool expand_joints = false;         // expand URDF floating/planar joints instead of failing
};

// `source` is either URDF XML (first non-blank character '<') or a file path. A link whose inertia
// violates the triangle inequality (triangle_inequality_violation; no rigid body has it, but URDF
// files in use carry such inertias, e.g. example-robot-data's go1, b1, anymal and hyq bases) is loaded
// as given, with a sentence naming the link appended to `warnings` (if given).
Model model_from_urdf(const std::string& source, const UrdfOptions& options = {},
                      std::vector<std::string>* warnings = nullptr);

}  // namespace hovi
