#include "hovi/algorithms/stacked_constraints.hpp"

namespace hovi {

void constraint_values(const Model& model, const KinematicsView& kin, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<VecX> h) {
  int row = 0;
  for (const auto& c : model.constraints) {
    c->value(kin, q, h.segment(row, c->dim()));
    row += c->dim();
  }
}

void constraint_jacobian(const Model& model, const KinematicsView& kin, Eigen::Ref<MatX> J) {
  int row = 0;
  for (const auto& c : model.constraints) {
    c->jacobian(kin, J.middleRows(row, c->dim()));
    row += c->dim();
  }
}

Model with_constraint_forces(const Model& model) {
  Model aug = model;
  aug.constraints.clear();
  for (const auto& c : model.constraints) {
    const int first = aug.n_controls();
    for (int k = 0; k < c->dim(); ++k) aug.add_control();
    c->add_force_elements(aug, first);
  }
  return aug;
}

}  // namespace hovi
