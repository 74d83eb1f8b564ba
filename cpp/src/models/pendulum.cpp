#include "hovi/models/pendulum.hpp"

#include "hovi/errors.hpp"

namespace hovi::models {

Model pendulum(int n, double length, double mass, double radius) {
  if (n < 1) throw ModelError("pendulum: the number of links must be at least 1, got " + std::to_string(n));
  if (!(length > 0) || !(mass > 0) || !(radius > 0))
    throw ModelError("pendulum: length, mass and radius must be positive");
  const double transverse = mass * (3 * radius * radius + length * length) / 12;
  const double axial = mass * radius * radius / 2;
  Model model;
  for (int i = 0; i < n; ++i) {
    BodySpec s;
    s.name = "link" + std::to_string(i + 1);
    s.joint_name = "joint" + std::to_string(i + 1);
    s.parent = i - 1;
    s.type = JointType::Revolute;
    s.axis = i % 2 == 0 ? Vec3::UnitX() : Vec3::UnitY();
    s.placement = SE3::Translation(i == 0 ? Vec3::Zero() : Vec3(0, 0, -length));
    s.mass = mass;
    s.com = Vec3(0, 0, -length / 2);
    s.inertia = Vec3(transverse, transverse, axial).asDiagonal();
    model.add_body(s);
  }
  return model;
}

}  // namespace hovi::models
