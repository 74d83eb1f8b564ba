#include "hovi/integrators/linearizer.hpp"

#include <Eigen/LU>

namespace hovi {

Linearizer::Linearizer(const Model& model, const Quadrature& quad, double dt)
    : model_(model), quad_(quad), dt_(dt), ws_(model, quad),
      Jq_((quad.s + 1) * model.n(), (quad.s + 1) * model.n()) {}

void Linearizer::del_jacobian(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX& Jq, MatX* Ju) {
  const int N = (quad_.s + 1) * model_.n();
  Jq.resize(N, N);
  hovi::del_jacobian(model_, quad_, ws_, qc, u, dt_, Jq, Ju);
}

bool Linearizer::step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX* A, MatX* B) {
  const int n = model_.n(), s = quad_.s, m = model_.n_controls(), sn = s * n;
  const bool want_u = B != nullptr && m > 0;
  del_jacobian(qc, u, Jq_, want_u ? &Ju_ : nullptr);
  const Eigen::PartialPivLU<MatX> lu(Jq_.topRightCorner(sn, sn));  // dR/dz
  const double scale = Jq_.topRightCorner(sn, sn).cwiseAbs().maxCoeff();
  if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;
  const auto P_z = Jq_.bottomRightCorner(n, sn);  // dp^{k+1}/dz
  if (A) {
    // right-hand sides: dR/dq^k (first block column) and dR/dp^k = [I; 0]
    rhs_.setZero(sn, 2 * n);
    rhs_.leftCols(n) = Jq_.topLeftCorner(sn, n);
    rhs_.block(0, n, n, n).setIdentity();
    sol_ = -lu.solve(rhs_);
    A->resize(2 * n, 2 * n);
    A->topRows(n) = sol_.bottomRows(n);
    A->bottomRows(n).noalias() = P_z * sol_;
    A->bottomLeftCorner(n, n) += Jq_.bottomLeftCorner(n, n);
  }
  if (B) {
    B->setZero(2 * n, (s + 1) * m);
    if (want_u) {
      sol_ = -lu.solve(Ju_.topRows(sn));
      B->topRows(n) = sol_.bottomRows(n);
      B->bottomRows(n).noalias() = P_z * sol_;
      B->bottomRows(n) += Ju_.bottomRows(n);
    }
  }
  return true;
}

}  // namespace hovi
