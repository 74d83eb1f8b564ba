#include "hovi/integrators/linearizer.hpp"

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "hovi/algorithms/kinematics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

Linearizer::Linearizer(const GalerkinIntegrator& integ)
    : model_(integ.model()), quad_(integ.quadrature()), dt_(integ.dt()), mc_(model_.n_constraints()),
      nz_(integ.contacts().unknowns()), aug_(mc_ ? with_constraint_forces(model_) : model_),
      pool_([this] { return std::make_unique<Workspace>(aug_, model_, quad_); }) {
  if (model_.rotation_chart >= 0) free_ = std::make_unique<FreeBaseJacobians>(model_, quad_, dt_);
  if (integ.has_contacts()) contact_ = std::make_unique<ContactJacobians>(model_, quad_, dt_, integ.contacts(), free_.get());
}

void Linearizer::del_jacobian(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX& Jq, MatX* Ju,
                              const Eigen::Ref<const MatX>& lambda, MatX* Dh) const {
  model_.refuse_free_base("the DEL Jacobian in joint coordinates (del_jacobian; step_jacobians works)");
  auto w = pool_.acquire();
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls();
  Jq.resize(S1 * n, S1 * n);
  if (!mc_) {
    hovi::del_jacobian(model_, quad_, w->ws, qc, u, dt_, Jq, Ju);
    return;
  }
  w->uaug.setZero(m + mc_, S1);
  w->uaug.topRows(m) = u;
  w->uaug.bottomLeftCorner(mc_, s) = lambda;
  hovi::del_jacobian(aug_, quad_, w->ws, qc, w->uaug, dt_, Jq, Ju);
  if (Dh) {
    Dh->setZero(s * mc_, S1 * n);
    for (int a = 1; a <= s; ++a) {
      forward_kinematics(model_, w->data, qc.col(a));
      constraint_jacobian(model_, KinematicsView{model_, w->data.g.data(), w->data.Sbar.data(), 1},
                          Dh->block((a - 1) * mc_, a * n, mc_, n));
    }
  }
}

bool Linearizer::step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, MatX* A, MatX* B,
                                const Eigen::Ref<const MatX>& lambda, MatX* Yx, MatX* Yu, double smoothing,
                                const Eigen::Ref<const VecX>& start) const {
  if (smoothing != 0 && !contact_) throw InputError("smoothing is for an integrator with contacts");
  Mat3 centre;  // a free base: the chart's, q^k's attitude
  if (free_) {
    if (Yx || Yu) model_.refuse_free_base("the control points' sensitivities (FDDP)");
    if (start.size() != model_.nq())
      throw InputError("a free base's linearisation needs the step's start q (" + std::to_string(model_.nq()) +
                       " entries)");
    VecX q(model_.n());
    free_->base().split(start, q, centre);
    if (!contact_) return free_->step_jacobians(qc, u, centre, A, B);
  }
  if (!(smoothing >= 0) || !std::isfinite(smoothing)) throw InputError("smoothing must be finite and >= 0");
  if (contact_) {  // the contact step; s = 1: its one unknown control point is q^{k+1}, the top rows of A and B
    if ((Yx || Yu) && quad_.s != 1) throw InputError("the control points' sensitivities through contact need s = 1");
    if ((Yx && !A) || (Yu && !B)) throw InputError("Yx and Yu through contact come with A and B");
    if (lambda.size() != nz_)
      throw InputError("a contact step's linearisation needs its " + std::to_string(nz_) + " impulses");
    const Eigen::Map<const VecX> z(lambda.data(), lambda.size());
    const Mat3* c = free_ ? &centre : nullptr;
    const bool ok = smoothing > 0 ? contact_->smoothed_jacobians(qc, u, z, smoothing, A, B, c)
                              : contact_->step_jacobians(qc, u, z, A, B, c);
    if (ok && Yx) *Yx = A->topRows(model_.n());
    if (ok && Yu) *Yu = B->topRows(model_.n());
    return ok;
  }
  auto w = pool_.acquire();
  MatX &uaug = w->uaug, &Jq = w->Jq, &Ju = w->Ju, &K = w->K, &rhs = w->rhs, &sol = w->sol, &Dh = w->Dh;
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), mc = mc_;
  const int sn = s * n, ny = sn + s * mc, ma = m + mc;  // unknowns y = (q^{k,1..s}, λ^{k,0..s-1})
  const bool want_u = B != nullptr && m > 0;
  // The augmented controls [u; λ] (λ^{k,s} = 0) and the Jacobians of the augmented equations.
  uaug.setZero(ma, S1);
  uaug.topRows(m) = u;
  if (mc) uaug.bottomLeftCorner(mc, s) = lambda;
  Jq.resize(S1 * n, S1 * n);
  hovi::del_jacobian(aug_, quad_, w->ws, qc, uaug, dt_, Jq, (want_u || mc) ? &Ju : nullptr);
  // dR/dy: [[dr/dz, dr/dλ], [Dh, 0]]
  K.setZero(ny, ny);
  K.topLeftCorner(sn, sn) = Jq.topRightCorner(sn, sn);
  if (mc) {
    Dh.resize(mc, n);
    for (int a = 0; a < S1; ++a) {
      forward_kinematics(model_, w->data, qc.col(a));
      constraint_jacobian(model_, KinematicsView{model_, w->data.g.data(), w->data.Sbar.data(), 1}, Dh);
      if (a < s)  // dr^a/dλ^a: the multiplier columns of Ju at control point a
        K.block(a * n, sn + a * mc, n, mc) = Ju.block(a * n, a * ma + m, n, mc);
      if (a >= 1) K.block(sn + (a - 1) * mc, (a - 1) * n, mc, n) = Dh;  // dh(q^a)/dq^a
    }
  }
  const Eigen::PartialPivLU<MatX> lu(K);
  const double scale = K.cwiseAbs().maxCoeff();
  if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;
  const auto P_z = Jq.bottomRightCorner(n, sn);  // dp^{k+1}/dz; p^{k+1} has no λ (λ^{k,s} = 0)
  if (A) {
    // right-hand sides: dR/dq^k (first block column) and dR/dp^k = [I; 0]
    rhs.setZero(ny, 2 * n);
    rhs.topLeftCorner(sn, n) = Jq.topLeftCorner(sn, n);
    rhs.block(0, n, n, n).setIdentity();
    sol = -lu.solve(rhs);
    A->resize(2 * n, 2 * n);
    A->topRows(n) = sol.middleRows(sn - n, n);
    A->bottomRows(n).noalias() = P_z * sol.topRows(sn);
    A->bottomLeftCorner(n, n) += Jq.bottomLeftCorner(n, n);
    if (Yx) *Yx = sol.topRows(sn);
  }
  if (B) {
    B->setZero(2 * n, S1 * m);
    if (want_u) {
      rhs.setZero(ny, S1 * m);
      for (int a = 0; a < S1; ++a) rhs.block(0, a * m, sn, m) = Ju.block(0, a * ma, sn, m);
      sol = -lu.solve(rhs);
      B->topRows(n) = sol.middleRows(sn - n, n);
      B->bottomRows(n).noalias() = P_z * sol.topRows(sn);
      for (int a = 0; a < S1; ++a) B->block(n, a * m, n, m) += Ju.block(sn, a * ma, n, m);
      if (Yu) *Yu = sol.topRows(sn);
    } else if (Yu) {
      Yu->setZero(sn, S1 * m);
    }
  }
  return true;
}

int Linearizer::trajectory_jacobians(const Eigen::Ref<const MatX>& C, const Eigen::Ref<const MatX>& U,
                                     const Eigen::Ref<const MatX>& W, double* As, double* Bs, double smoothing,
                                     const Eigen::Ref<const MatX>& starts) const {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls();
  const int rows = contact_ ? static_cast<int>(W.cols()) : mc_, cols = contact_ ? 1 : s;  // one step's w
  MatX A, B, qc(n, S1), uk(m, S1), wk(rows, cols);
  if (free_ && (starts.rows() != C.rows() || starts.cols() != model_.nq()))
    throw InputError("a free base's linearisation needs every step's start q (steps x " +
                     std::to_string(model_.nq()) + ")");
  for (int k = 0; k < C.rows(); ++k) {
    for (int c = 0; c < S1; ++c) qc.col(c) = C.row(k).segment(c * n, n).transpose();
    for (int c = 0; c < S1; ++c) uk.col(c) = U.row(k).segment(c * m, m).transpose();
    for (int c = 0; c < cols && rows; ++c) wk.col(c) = W.row(k).segment(c * rows, rows).transpose();
    const VecX start = free_ ? VecX(starts.row(k).transpose()) : VecX();
    if (!step_jacobians(qc, uk, As ? &A : nullptr, Bs ? &B : nullptr, wk, nullptr, nullptr, smoothing, start))
      return k;
    if (As) Eigen::Map<RowMajor>(As + std::size_t(k) * 4 * n * n, 2 * n, 2 * n) = A;
    if (Bs) Eigen::Map<RowMajor>(Bs + std::size_t(k) * 2 * n * S1 * m, 2 * n, S1 * m) = B;
  }
  return -1;
}

}  // namespace hovi
