// All of a model's holonomic constraints together (model/constraint.hpp): the stacked values h(q)
// and Jacobian Dh, and the model whose force elements apply Dh^T λ (the constrained integrator's
// augmented model).
#pragma once
#include "hovi/model/constraint.hpp"
#include "hovi/model/model.hpp"

namespace hovi {

// All of a model's constraints stacked (rows in the order they were added).
void constraint_values(const Model& model, const KinematicsView& kin, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<VecX> h);
void constraint_jacobian(const Model& model, const KinematicsView& kin, Eigen::Ref<MatX> J);
// The model plus every constraint's force elements, the multipliers appended to the controls:
// u_augmented = [u; λ]. The augmented model has no constraints of its own.
Model with_constraint_forces(const Model& model);

}  // namespace hovi
