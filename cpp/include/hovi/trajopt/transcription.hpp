// A transcription turns the dynamics of a trajectory-optimisation problem into equality
// constraints g(x) = 0 of a nonlinear program over a variable vector x, with the Jacobian's
// sparsity structure fixed at construction. It knows nothing of costs or of the solver.
//
// Stages: N of equal length dt; each transcription names its variables through offsets (see the
// concrete classes). Thread safety: constraints() and jacobian() may run concurrently.
#pragma once
#include "hovi/errors.hpp"
#include "hovi/spatial/types.hpp"

namespace hovi {

// How controls are parameterised: one value per time sample point (shared by neighbouring stages
// at the knots, so the control is continuous and piecewise polynomial), or one per stage (held).
enum class ControlMode { PerPoint, Held };

// Row and column indices of the Jacobian's nonzeros, in the order jacobian() writes values.
struct SparsityStructure {
  Eigen::VectorXi rows, cols;
  int nnz() const { return static_cast<int>(rows.size()); }
};

class Transcription {
 public:
  virtual ~Transcription() = default;
  virtual int n_variables() const = 0;
  virtual int n_constraints() const = 0;
  virtual const SparsityStructure& structure() const = 0;
  // g(x), n_constraints() entries.
  virtual void constraints(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> g) const = 0;
  // The Jacobian's values in structure() order, structure().nnz() entries.
  virtual void jacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> values) const = 0;
  // The Hessian of lambda^T g (lambda: n_constraints()) at x, if the transcription has one
  // (has_hessian()): entries of its lower triangle (rows >= cols; an entry may repeat, the values
  // add) in hessian_structure() order, on `threads` threads. Without one, a caller differences the
  // Jacobian (lagrangian_hessian.hpp).
  virtual bool has_hessian() const { return false; }
  virtual const SparsityStructure& hessian_structure() const { return no_hessian_; }
  virtual void hessian(const Eigen::Ref<const VecX>&, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX>, int) const {
    throw InputError("this transcription has no Hessian of its own");
  }

 private:
  SparsityStructure no_hessian_;
};

}  // namespace hovi
