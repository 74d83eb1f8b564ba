// External wrenches on bodies F̄_i(g_i, v̄_i, u) (paper Assumption 1): one interface with its
// derivatives, Wrenches are spatial (world frame, at the world
// origin, (torque, force)); g is the pose of the body's centre-of-mass frame {i}.
//
// D1 is the derivative with respect to g under a left (spatial) perturbation,
// D1 η = d/dt F̄(exp(t η^) g) (appendix C, docs/paper.md C-6); D2 = dF̄/dv̄; Du = dF̄/du.
// Implement BodyWrench in C++ to add a new kind of force (the built-in kinds: forces/builtin_wrenches.hpp).
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
  // What the wrench's second derivatives can skip (del_hessian.hpp): false unless F̄ never depends on
  // v̄ / is affine in u (then D2 = 0 / Du does not depend on u).
  virtual bool velocity_free() const { return false; }
  virtual bool control_affine() const { return false; }
  // A constant world force at a body point, scaled by a control (-1: none), is the gradient of
  // u_c force . x(q): its second derivatives are the point's kinematics' (body_points.hpp), not
  // differences (del_hessian.hpp). True for such a wrench, with its point (COM frame), force and
  // control; false for any other.
  virtual bool world_point_force(Vec3& point, Vec3& force, int& control) const { return false; }
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

}  // namespace hovi
