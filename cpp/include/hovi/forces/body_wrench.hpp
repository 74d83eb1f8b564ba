// External wrenches on bodies F̄_i(g_i, v̄_i, u) (paper Assumption 1): one interface with its
// derivatives, and the built-in elements. Wrenches are spatial (world frame, at the world
// origin, (torque, force)); g is the pose of the body's centre-of-mass frame {i}.
//
// D1 is the derivative with respect to g under a left (spatial) perturbation,
// D1 η = d/dt F̄(exp(t η^) g) (appendix C, ERRATA C-6); D2 = dF̄/dv̄; Du = dF̄/du.
// Implement BodyWrench in C++ to add a new kind of force.
#pragma once
#include <memory>

#include "hovi/spatial/algebra.hpp"
#include "hovi/util/byte_stream.hpp"

namespace hovi {

class BodyWrench {
 public:
  explicit BodyWrench(int body) : body_(body) {}
  virtual ~BodyWrench() = default;
  int body() const { return body_; }

  virtual Wrench value(const SE3& g, const Twist& v, const VecX& u) const = 0;
  // Adds (not assigns) D1 and D2 into the given matrices.
  virtual void add_derivatives(const SE3& g, const Twist& v, const VecX& u, Mat6& D1, Mat6& D2) const = 0;
  // Adds dF̄/du (6 x m) into Du.
  virtual void add_control_jacobian(const SE3& g, const Twist& v, const VecX& u, Eigen::Ref<MatX> Du) const = 0;
  // The largest control index used, -1 if none (the model checks it against its controls).
  virtual int max_control_index() const { return -1; }
  virtual const char* kind() const = 0;
  // Writes the parameters (body included) that the kind's load() reads back (model_serialization.hpp);
  // throws ModelError for a kind that cannot be serialised (the default).
  virtual void save(ByteWriter& out) const;

 private:
  int body_;
};

// D1 of a force f with world-fixed components applied at the world point x (gravity is the
// case f = m g at the COM): [[f^ x^, -f^], [0, 0]].
Mat6 world_force_D1(const Vec3& f, const Vec3& x);

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
  const char* kind() const override { return "drag"; }
  void save(ByteWriter& out) const override;
  static std::shared_ptr<const BodyDrag> load(ByteReader& in);

 private:
  SpatialInertia C_;  // C in the body frame, stored as an inertia-like tensor
};

}  // namespace hovi
