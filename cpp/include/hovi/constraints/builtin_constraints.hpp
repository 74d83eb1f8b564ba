// The built-in holonomic constraints (the interface, Constraint, is model/constraint.hpp): a body
// point held at a world point, a loop closure, a held orientation and a linear joint coupling.
#pragma once
#include <memory>

#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/model/constraint.hpp"
#include "hovi/model/model.hpp"
#include "hovi/util/byte_stream.hpp"

namespace hovi {

// Rows of the world axes that a constraint keeps, e.g. "xz" for planar use: a k x 3 selector.
Eigen::Matrix<double, Eigen::Dynamic, 3> axes_selector(const std::string& axes);

// A point r of a body (in its COM frame) held at a world point: h = P (g r - target).
class PointConstraint : public Constraint {
 public:
  PointConstraint(int body, const Vec3& point, const Vec3& target, const std::string& axes = "xyz");
  int dim() const override { return static_cast<int>(P_.rows()); }
  const char* kind() const override { return "point"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const PointConstraint> load(ByteReader& in);
  void check(const Model& model) const override;
  void value(const KinematicsView& kin, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const override;
  void jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const override;
  void add_force_elements(Model& augmented, int first) const override;

 private:
  int body_;
  Vec3 point_, target_;
  std::string axes_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> P_;
};

// A point r1 of body1 coincident with a point r2 of body2 (a loop closure): h = P (x1 - x2).
class LoopConstraint : public Constraint {
 public:
  LoopConstraint(int body1, const Vec3& point1, int body2, const Vec3& point2, const std::string& axes = "xyz");
  int dim() const override { return static_cast<int>(P_.rows()); }
  const char* kind() const override { return "loop"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const LoopConstraint> load(ByteReader& in);
  void check(const Model& model) const override;
  void value(const KinematicsView& kin, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const override;
  void jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const override;
  void add_force_elements(Model& augmented, int first) const override;

 private:
  int body1_, body2_;
  Vec3 point1_, point2_;
  std::string axes_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> P_;
};

// A body's orientation held at R0: h = ((R e_y)·(R0 e_z), (R e_z)·(R0 e_x), (R e_x)·(R0 e_y)),
// zero at R = R0 with Dh = R0^T ω there (valid near R0, where it is used).
class OrientationConstraint : public Constraint {
 public:
  OrientationConstraint(int body, const Mat3& R0);
  int dim() const override { return 3; }
  const char* kind() const override { return "orientation"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const OrientationConstraint> load(ByteReader& in);
  void check(const Model& model) const override;
  void value(const KinematicsView& kin, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const override;
  void jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const override;
  void add_force_elements(Model& augmented, int first) const override;

 private:
  int body_;
  Mat3 R0_;
};

// A linear coupling of joint coordinates: h = c^T q - offset (one equation).
class JointCoupling : public Constraint {
 public:
  JointCoupling(const VecX& coefficients, double offset);
  int dim() const override { return 1; }
  const char* kind() const override { return "joint_coupling"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const JointCoupling> load(ByteReader& in);
  void check(const Model& model) const override;
  void value(const KinematicsView& kin, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const override;
  void jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const override;
  void add_force_elements(Model& augmented, int first) const override;

 private:
  VecX c_;
  double offset_;
};

// The torque u[control] (R a × d) aligning a body axis a (body frame) with a world axis d: the
// force element of OrientationConstraint. D1 = [[u d^ (R a)^, 0], [0, 0]], D2 = 0.
class AlignmentTorque : public BodyWrench {
 public:
  AlignmentTorque(int body, const Vec3& body_axis, const Vec3& world_axis, int control);
  Wrench value(const SE3& g, const Twist& v, const VecX& u) const override;
  void add_derivatives(const SE3& g, const Twist& v, const VecX& u, Mat6& D1, Mat6& D2) const override;
  void add_control_jacobian(const SE3& g, const Twist& v, const VecX& u, Eigen::Ref<MatX> Du) const override;
  int max_control_index() const override { return control_; }
  const char* kind() const override { return "alignment_torque"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const AlignmentTorque> load(ByteReader& in);

 private:
  Vec3 a_, d_;
  int control_;
};

}  // namespace hovi
