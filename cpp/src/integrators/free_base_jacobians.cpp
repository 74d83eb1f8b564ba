#include "hovi/integrators/free_base_jacobians.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/util/central_differences.hpp"

namespace hovi {

TangentStep::TangentStep(const FreeBase& base, const Mat3& centre, const Eigen::Ref<const MatX>& qc, const VecX& p0,
                         const VecX& pn)
    : base_(base), n_(int(qc.rows())), j_(base.joint()), C_(centre) {
  const RotationChart& chart = base.chart;
  const Vec3 theta = qc.col(qc.cols() - 1).segment<3>(j_);
  Rs_ = chart.rotation(theta);
  R1_ = C_ * Rs_;
  E_ = chart.rates_to_omega(theta);
  Et_.compute(E_.transpose());
  p_lin0_ = C_.transpose() * p0.head<3>();
  p_lin1_ = R1_.transpose() * pn.head<3>();
  const Vec3 w_ang = Et_.solve(Vec3(pn.segment<3>(j_)));
  for (int k = 0; k < 3; ++k) M_.col(k) = chart.rates_to_omega_rate(theta, Vec3::Unit(k)).transpose() * w_ang;
}

MatX TangentStep::inputs(const MatX& d_q0, const MatX& d_turn, bool with_p) const {
  // q^{k,0}'s position moves by C δv, the centre turns by δω, the joints by δr; the chart momentum
  // p^k = diag(C, E(0)^T, 1) p turns with the centre: d(C p_v) = -C p̂_v δω.
  const int n = n_, j = j_, nr = n - j - 3, rows = int(d_q0.rows());
  MatX X = MatX::Zero(rows, 2 * n);
  X.leftCols(3) = d_q0.leftCols(3) * C_;
  X.middleCols(j, 3) = d_turn;
  X.middleCols(j + 3, nr) = d_q0.middleCols(j + 3, nr);
  if (with_p) {
    X.block(0, j, 3, 3) -= C_ * hat(p_lin0_);
    X.block(0, n, 3, 3) += C_;
    X.block(j, n + j, 3, 3) += base_.chart.rates_to_omega(Vec3::Zero()).transpose();
    X.block(j + 3, n + j + 3, nr, nr) += MatX::Identity(nr, nr);
  }
  return X;
}

MatX TangentStep::turn() const {
  MatX W = MatX::Zero(3, 2 * n_);
  W.middleCols(j_, 3).setIdentity();
  return W;
}

void TangentStep::outputs(const MatX& dq_end, const MatX& dp_end, const MatX& turn, MatX& out) const {
  // q^{k+1} = (x, C R(θ^s), r): δω^{k+1} = R(θ^s)^T δω + E(θ^s) dθ^s, δv^{k+1} = R1^T dx; its public
  // momentum (R1^T p_x, E^-T p_θ, p_r) through both.
  const int n = n_, j = j_;
  out.resize(2 * n, dq_end.cols());
  out.topRows(n) = dq_end;
  out.topRows(3) = R1_.transpose() * dq_end.topRows(3);
  out.middleRows(j, 3) = E_ * dq_end.middleRows(j, 3) + Rs_.transpose() * turn;
  out.bottomRows(n) = dp_end;
  out.middleRows(n, 3) = R1_.transpose() * dp_end.topRows(3) + hat(p_lin1_) * out.middleRows(j, 3);
  out.middleRows(n + j, 3) = Et_.solve(dp_end.middleRows(j, 3) - M_ * dq_end.middleRows(j, 3));
}

FreeBaseJacobians::FreeBaseJacobians(const Model& model, const Quadrature& quad, double dt)
    : model_(model), quad_(quad), dt_(dt), base_(model),
      pool_([this] { return std::make_unique<Workspace>(model_, quad_); }) {}

void FreeBaseJacobians::turn_derivative(DelWorkspace& res, const Eigen::Ref<const MatX>& qc,
                                        const Eigen::Ref<const MatX>& u, const Mat3& centre,
                                        const std::function<VecX(const SE3&)>* knot, MatX& dR_dw) const {
  const int n = model_.n(), s = quad_.s, sn = s * n;
  const VecX zero = VecX::Zero(n);
  MatX rp(n, s), rm(n, s);
  VecX pp(n), pm(n);
  dR_dw.resize(sn + n, 3);
  for (int l = 0; l < 3; ++l) {
    const Mat3 turn = Eigen::AngleAxisd(kCentralStep, Vec3::Unit(l)).toRotationMatrix();
    const SE3 plus = model_.chart_placement(centre * turn), minus = model_.chart_placement(centre * turn.transpose());
    res.chart_placement = plus;
    del_residual(model_, quad_, res, qc, zero, u, dt_, rp, pp);
    res.chart_placement = minus;
    del_residual(model_, quad_, res, qc, zero, u, dt_, rm, pm);
    if (knot) {
      rp.col(0) += (*knot)(plus);
      rm.col(0) += (*knot)(minus);
    }
    dR_dw.col(l).head(sn) = Eigen::Map<const VecX>(rp.data(), sn) - Eigen::Map<const VecX>(rm.data(), sn);
    dR_dw.col(l).tail(n) = pp - pm;
  }
  dR_dw /= 2 * kCentralStep;
  res.chart_placement = model_.chart_placement(centre);
}

bool FreeBaseJacobians::step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                                       const Mat3& centre, MatX* A, MatX* B) const {
  auto w = pool_.acquire();
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), sn = s * n;
  const bool want_u = B != nullptr && m > 0;
  w->jac.data.chart_placement = w->res.chart_placement = model_.chart_placement(centre);
  w->zero.setZero(n);
  MatX &Jq = w->Jq, &Ju = w->Ju;
  Jq.resize(S1 * n, S1 * n);
  del_jacobian(model_, quad_, w->jac, qc, u, dt_, Jq, want_u ? &Ju : nullptr);
  w->r.resize(n, s);
  w->pn.resize(n);
  del_residual(model_, quad_, w->res, qc, w->zero, u, dt_, w->r, w->pn);
  const VecX p0 = -w->r.col(0);  // r^{k,0} = p^k + ...: the step's chart momentum p^k
  add_centre_term_jacobian(model_, quad_, dt_, qc, w->r, MatX(w->res.chart_P), w->jac, Jq, want_u ? &Ju : nullptr);
  turn_derivative(w->res, qc, u, centre, nullptr, w->dR_dw);

  const Eigen::PartialPivLU<MatX> lu(Jq.topRightCorner(sn, sn));
  const double scale = Jq.topRightCorner(sn, sn).cwiseAbs().maxCoeff();
  if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;
  const TangentStep step(base_, centre, qc, p0, w->pn);
  const auto P_y = Jq.bottomRightCorner(n, sn);
  if (A) {
    w->sol = -lu.solve(step.inputs(Jq.topLeftCorner(sn, n), w->dR_dw.topRows(sn), true));
    const MatX Pd = step.inputs(Jq.bottomLeftCorner(n, n), w->dR_dw.bottomRows(n), false);
    step.outputs(w->sol.bottomRows(n), P_y * w->sol + Pd, step.turn(), *A);
  }
  if (B) {
    if (want_u) {
      w->sol = -lu.solve(Ju.topRows(sn));
      step.outputs(w->sol.bottomRows(n), P_y * w->sol + Ju.bottomRows(n), MatX::Zero(3, S1 * m), *B);
    } else {
      B->setZero(2 * n, S1 * m);
    }
  }
  return true;
}

}  // namespace hovi
