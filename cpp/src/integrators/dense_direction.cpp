#include "hovi/integrators/dense_direction.hpp"

#include <algorithm>
#include <cmath>

#include "hovi/algorithms/rotation_chart.hpp"

namespace hovi {

bool dense_direction_is_faster(const Model& model, int s) {
  // Largest n at which the dense path won, s = 1..4 (bench/results/direction_crossover.json);
  // beyond s = 4 the last entry.
  static constexpr int crossover[] = {0, 48, 48, 48, 32};
  return model.n() <= crossover[std::min(std::max(s, 1), 4)];
}

DenseDirection::DenseDirection(const Model& model, const Quadrature& quad)
    : ws_(model, quad), J_(quad.s * model.n(), quad.s * model.n()),
      lu_(quad.s * model.n()), x_(quad.s * model.n()), y_(quad.s * model.n()) {}

bool DenseDirection::factor(const Model& model, const Quadrature& quad, const Eigen::Ref<const MatX>& qc,
                            const Eigen::Ref<const MatX>& u, double dt, const DelWorkspace* kinematics,
                            const MatX* r) {
  del_jacobian(model, quad, ws_, qc, u, dt, J_, nullptr, kinematics, BlockWindow::newton(quad.s));
  if (model.rotation_chart >= 0 && kinematics && r)
    add_centre_term_jacobian(model, quad, dt, qc, *r, kinematics->chart_P, ws_, J_, nullptr, 1);
  lu_.compute(J_);
  // Singular to working precision: a pivot below 1e-14 of J's largest entry (the test of the
  // recursive path's pivot blocks), cheaper than Eigen's rcond() estimate (bench/README.md).
  const double scale = J_.cwiseAbs().maxCoeff();
  return std::isfinite(scale) && scale > 0 && lu_.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale;
}

void DenseDirection::solve(const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  x_ = Eigen::Map<const VecX>(r.data(), r.size());
  y_.noalias() = lu_.solve(x_);
  for (int g = 0; g < dq.cols(); ++g) dq.col(g) = -y_.segment(g * dq.rows(), dq.rows());
}

void DenseDirection::solve_many(const Eigen::Ref<const MatX>& R, Eigen::Ref<MatX> X) {
  X.noalias() = lu_.solve(R);
  X = -X;
}

}  // namespace hovi
