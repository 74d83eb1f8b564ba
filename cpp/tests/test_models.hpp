// Models shared by the C++ tests.
#pragma once
#include <initializer_list>
#include <random>
#include <string>

#include "hovi/model/model.hpp"
#include "hovi/models/pendulum.hpp"

namespace hovi::test_models {

// The BodySpec of body `name` on joint "<name>_joint" (the tests' models).
inline BodySpec body_spec(const char* name, int parent, JointType type, const Vec3& axis, const SE3& placement,
                          double mass, const Vec3& com, const Mat3& inertia) {
  BodySpec s;
  s.name = name;
  s.joint_name = std::string(name) + "_joint";
  s.parent = parent;
  s.type = type;
  s.axis = axis;
  s.placement = placement;
  s.mass = mass;
  s.com = com;
  s.inertia = inertia;
  return s;
}

// A branched tree exercising everything the algorithms must handle: two prismatic joints, skewed
// axes, rotated joint frames, offset centres of mass and full (non-diagonal) rotational inertias.
inline Model branched_tree() {
  Model m;
  int count = 0;
  auto body = [&](const char* name, int parent, JointType t, Vec3 axis, Vec3 pos, double mass) {
    Mat3 A;
    A << 0.3, 0.1, -0.2, 0.05, 0.4, 0.1, -0.1, 0.2, 0.5;
    A += 0.1 * count * Mat3::Identity();
    const SE3 placement(exp_twist((Twist() << 0.3, -0.2, 0.5, 0, 0, 0).finished(), 1.0 + 0.1 * count).R, pos);
    const Vec3 com = Vec3(0.05, -0.1, 0.2) * (1 + 0.2 * count);
    ++count;
    return m.add_body(body_spec(name, parent, t, axis, placement, mass, com, 0.1 * (A * A.transpose() + Mat3::Identity())));
  };
  const int a = body("a", -1, JointType::Revolute, Vec3(0, 0, 1), Vec3(0, 0, 0), 2.0);
  const int b = body("b", a, JointType::Prismatic, Vec3(1, 1, 0), Vec3(0.2, 0, 0.1), 1.0);
  body("c", b, JointType::Revolute, Vec3(0.2, 1, 0.3), Vec3(0, 0.3, 0), 0.7);
  const int d = body("d", a, JointType::Revolute, Vec3(1, 0, 0), Vec3(0, -0.2, 0.4), 1.3);
  body("e", d, JointType::Revolute, Vec3(0, 1, 0), Vec3(0.1, 0.1, 0.1), 0.4);
  body("f", d, JointType::Prismatic, Vec3(0, 0.3, 1), Vec3(-0.1, 0.2, 0.0), 0.6);
  return m;
}

// n numbers uniform in [lo, hi].
inline VecX uniform(std::mt19937& rng, int n, double lo, double hi) {
  std::uniform_real_distribution<double> dist(lo, hi);
  VecX x(n);
  for (int i = 0; i < n; ++i) x[i] = dist(rng);
  return x;
}

// `m` with springs (joint, stiffness, rest angle), dampers (joint, coefficient) and actuators (joint, gear).
struct JointForce {
  int joint;
  double a, b = 0;
};
inline Model with_forces(Model m, std::initializer_list<JointForce> springs, std::initializer_list<JointForce> dampers,
                         std::initializer_list<JointForce> actuators) {
  for (const JointForce& f : springs) m.add_spring(f.joint, f.a, f.b);
  for (const JointForce& f : dampers) m.add_damper(f.joint, f.a);
  for (const JointForce& f : actuators) m.add_actuator(f.joint, f.a);
  return m;
}

// The 5-link pendulum with springs (one with a nonzero rest angle, i.e. a preload), dampers and
// two actuators (one geared).
inline Model forced_pendulum() {
  return with_forces(models::pendulum(5), {{0, 3.0, 0.2}, {3, 1.5, -0.1}}, {{1, 0.4}, {4, 0.2}}, {{2, 1.0}, {4, 2.0}});
}

// A floating chain: x, y, z sliders, yaw (z), pitch (y), roll (x) turning a body of principal moments
// 1, 2, 3 kg m^2, and an arm on a skewed revolute joint; the chart on the yaw, pitch and roll joints.
inline Model floating_chain(bool gravity) {
  Model m;
  auto add = [&](const char* name, int parent, JointType type, Vec3 axis, double mass, Mat3 inertia, Vec3 at,
                 Vec3 com) {
    return m.add_body(body_spec(name, parent, type, axis, SE3::Translation(at), mass, com, inertia));
  };
  const Mat3 Z = Mat3::Zero();
  int b = add("x", -1, JointType::Prismatic, Vec3::UnitX(), 0, Z, Vec3::Zero(), Vec3::Zero());
  b = add("y", b, JointType::Prismatic, Vec3::UnitY(), 0, Z, Vec3::Zero(), Vec3::Zero());
  b = add("z", b, JointType::Prismatic, Vec3::UnitZ(), 0, Z, Vec3::Zero(), Vec3::Zero());
  b = add("yaw", b, JointType::Revolute, Vec3::UnitZ(), 0, Z, Vec3::Zero(), Vec3::Zero());
  b = add("pitch", b, JointType::Revolute, Vec3::UnitY(), 0, Z, Vec3::Zero(), Vec3::Zero());
  b = add("body", b, JointType::Revolute, Vec3::UnitX(), 2.0, Vec3(1, 2, 3).asDiagonal(), Vec3::Zero(),
          Vec3(0.02, -0.01, 0.03));
  add("arm", b, JointType::Revolute, Vec3(0.3, 1, 0.2).normalized(), 0.5, Vec3(0.02, 0.01, 0.02).asDiagonal(),
      Vec3(0.2, 0, 0.1), Vec3(0.15, 0, 0));
  if (!gravity) m.gravity.setZero();
  m.set_rotation_chart(3);
  return m;
}

}  // namespace hovi::test_models
