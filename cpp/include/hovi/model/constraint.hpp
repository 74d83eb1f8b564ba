// Holonomic constraints h(q) = 0 (paper Sec. 3.3, eq. DEL_general_c). Each constraint gives its
// value and Jacobian Dh at a configuration, and registers force elements whose generalized force
// is exactly Dh^T λ, with the multipliers λ entering as extra control inputs. The constrained
// integrator then reuses Algorithm 1, the recursive Newton direction and the linearisation on a
// model augmented with those elements; their Lie-group derivatives supply the λ·d²h terms.
// Implement Constraint in C++ to add a new kind (the built-in kinds: constraints/builtin_constraints.hpp).
#pragma once
#include "hovi/spatial/algebra.hpp"
#include "hovi/util/byte_stream.hpp"

namespace hovi {

class Model;

// The kinematics of every body at one configuration: body i's pose is g[i * stride] (the COM
// frame) and its spatial joint twist Sbar[i * stride].
struct KinematicsView {
  const Model& model;
  const SE3* g;
  const Twist* Sbar;
  int stride;
  const SE3& pose(int i) const { return g[i * stride]; }
  const Twist& twist(int i) const { return Sbar[i * stride]; }
};

class Constraint {
 public:
  virtual ~Constraint() = default;
  virtual int dim() const = 0;
  virtual const char* kind() const = 0;
  // Throws ModelError if the constraint does not fit the model (unknown body, ...).
  virtual void check(const Model& model) const = 0;
  // h(q), dim() entries.
  virtual void value(const KinematicsView& kin, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const = 0;
  // Dh = dh/dq, dim() x n (the rows are assigned, not added).
  virtual void jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const = 0;
  // Adds to `augmented` the elements whose generalized force is Dh^T λ with λ_k = u[first + k];
  // the controls first..first+dim()-1 already exist.
  virtual void add_force_elements(Model& augmented, int first) const = 0;
  // Writes the parameters that the kind's load() reads back (model_serialization.hpp); throws
  // ModelError for a kind that cannot be serialised (the default).
  virtual void save(ByteWriter& out) const;
};

}  // namespace hovi
