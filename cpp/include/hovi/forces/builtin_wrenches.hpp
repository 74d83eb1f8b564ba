// The built-in external wrenches on bodies (the interface, BodyWrench, is model/body_wrench.hpp):
// a wrench at a point of a body, and linear drag.
#pragma once
#include <memory>

#include "hovi/model/body_wrench.hpp"

namespace hovi {


// A wrench applied at a point r of the body (r in the COM frame {i}): force f and torque tau,
// with components fixed in the world (frame World) or turning with the body (frame Body),
// optionally scaled by one control input u[control].
class PointWrench : public BodyWrench {
 public:
  enum class Frame { World, Body };
  PointWrench(int body, const Vec3& point, const Vec3& force, const Vec3& torque, Frame frame, int control = -1);
  Wrench value(const SE3& g, const Twist& v, const VecX& u) const override;
  void add_derivatives(const SE3& g, const Twist& v, const VecX& u, Mat6& D1, Mat6& D2) const override;
  void add_control_jacobian(const SE3& g, const Twist& v, const VecX& u, Eigen::Ref<MatX> Du) const override;
  int max_control_index() const override { return control_; }
  bool velocity_free() const override { return true; }
  bool control_affine() const override { return true; }
  bool world_point_force(Vec3& point, Vec3& force, int& control) const override;
  const char* kind() const override { return "point_wrench"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const PointWrench> load(ByteReader& in);

 private:
  Wrench unit_value(const SE3& g) const;  // the wrench for a scale of 1
  double scale(const VecX& u) const { return control_ >= 0 ? u[control_] : 1.0; }
  Vec3 point_, force_, torque_;
  Frame frame_;
  int control_;
};

// Linear drag in the body frame at the COM: F = -C v with C = blockdiag(c_ang 1, c_lin 1),
// i.e. F̄ = -C̄ v̄ with C̄ = Ad^{-T} C Ad^{-1}; D2 = -C̄, D1 = -ad^D_F̄ - C̄ ad_v̄.
class BodyDrag : public BodyWrench {
 public:
  BodyDrag(int body, double linear, double angular);
  Wrench value(const SE3& g, const Twist& v, const VecX& u) const override;
  void add_derivatives(const SE3& g, const Twist& v, const VecX& u, Mat6& D1, Mat6& D2) const override;
  void add_control_jacobian(const SE3&, const Twist&, const VecX&, Eigen::Ref<MatX>) const override {}
  bool control_affine() const override { return true; }
  const char* kind() const override { return "drag"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const BodyDrag> load(ByteReader& in);

 private:
  SpatialInertia C_;  // C in the body frame, stored as an inertia-like tensor
};

}  // namespace hovi
