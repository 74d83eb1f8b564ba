#include "hovi/integrators/dense_direction.hpp"

#include <algorithm>
#include <cmath>

namespace hovi {

bool dense_direction_is_faster(const Model& model, int s) {
  // Largest n at which the dense path won, s = 1..4 (bench/results/direction_crossover.json);
  // beyond s = 4 the last entry.
  static constexpr int crossover[] = {0, 16, 24, 24, 24};
  return model.n() <= crossover[std::min(std::max(s, 1), 4)];
}

DenseDirection::DenseDirection(const Model& model, const Quadrature& quad)
    : ws_(model, quad), J_(quad.s * model.n(), quad.s * model.n()),
      lu_(quad.s * model.n()), x_(quad.s * model.n()) {}

bool DenseDirection::factor(const Model& model, const Quadrature& quad, const Eigen::Ref<const MatX>& qc,
                            const Eigen::Ref<const MatX>& u, double dt, const DelWorkspace* kinematics) {
  del_jacobian(model, quad, ws_, qc, u, dt, J_, nullptr, kinematics, BlockWindow::newton(quad.s));
  lu_.compute(J_);
  const double rcond = lu_.rcond();      // O((sn)^2) estimate of the reciprocal condition number
  return std::isfinite(rcond) && rcond > 1e-15;
}

void DenseDirection::solve(const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  x_ = Eigen::Map<const VecX>(r.data(), r.size());
  x_ = lu_.solve(x_);
  for (int g = 0; g < dq.cols(); ++g) dq.col(g) = -x_.segment(g * dq.rows(), dq.rows());
}

}  // namespace hovi
