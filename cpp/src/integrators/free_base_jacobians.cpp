#include "hovi/integrators/free_base_jacobians.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/util/central_differences.hpp"

namespace hovi {

FreeBaseJacobians::FreeBaseJacobians(const Model& model, const Quadrature& quad, double dt)
    : model_(model), quad_(quad), dt_(dt), base_(model),
      pool_([this] { return std::make_unique<Workspace>(model_, quad_); }) {}

void FreeBaseJacobians::residual(Workspace& w, const Eigen::Ref<const MatX>& q, const Eigen::Ref<const MatX>& u,
                                 MatX& r, VecX& p_next) const {
  r.resize(model_.n(), quad_.s);
  p_next.resize(model_.n());
  del_residual(model_, quad_, w.res, q, w.zero, u, dt_, r, p_next);
}

bool FreeBaseJacobians::step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                                       const Mat3& centre, MatX* A, MatX* B) const {
  auto w = pool_.acquire();
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), j = base_.joint(), sn = s * n;
  const int nr = n - j - 3;  // the joints after the base
  const bool want_u = B != nullptr && m > 0;
  const RotationChart& chart = base_.chart;
  const SE3 placement = model_.chart_placement(centre);
  w->jac.data.chart_placement = w->res.chart_placement = placement;
  w->zero.setZero(n);
  MatX &Jq = w->Jq, &Ju = w->Ju;
  Jq.resize(S1 * n, S1 * n);
  del_jacobian(model_, quad_, w->jac, qc, u, dt_, Jq, want_u ? &Ju : nullptr);
  residual(*w, qc, u, w->r, w->pn);
  const VecX p0 = -w->r.col(0);  // r^{k,0} = p^k + ...: the step's chart momentum p^k

  // The chart's rows of r^{k,0} (with its centre term) by central differences in q^{k,0..s} and u^{k,0..s}.
  auto chart_rows = [&](MatX& x, int row, int col, MatX& J, int Jcol) {
    const double x0 = x(row, col), step = kCentralStep * std::max(1.0, std::abs(x0));
    const double xp = x0 + step, xm = x0 - step;
    x(row, col) = xp;
    residual(*w, w->q, w->u, w->rp, w->pp);
    x(row, col) = xm;
    residual(*w, w->q, w->u, w->rm, w->pm);
    x(row, col) = x0;
    J.block(j, Jcol, 3, 1) = (w->rp.block(j, 0, 3, 1) - w->rm.block(j, 0, 3, 1)) / (xp - xm);
  };
  w->q = qc;
  w->u = u;
  for (int b = 0; b < S1; ++b)
    for (int i = 0; i < n; ++i) chart_rows(w->q, i, b, Jq, b * n + i);
  if (want_u)
    for (int a = 0; a < S1; ++a)
      for (int i = 0; i < m; ++i) chart_rows(w->u, i, a, Ju, a * m + i);
  // R's derivative by the centre's turn C exp(δω), every point's chart coordinates held.
  MatX& dR_dw = w->dR_dw;
  dR_dw.resize(sn + n, 3);
  for (int l = 0; l < 3; ++l) {
    const Mat3 turn = Eigen::AngleAxisd(kCentralStep, Vec3::Unit(l)).toRotationMatrix();
    w->res.chart_placement = model_.chart_placement(centre * turn);
    residual(*w, qc, u, w->rp, w->pp);
    w->res.chart_placement = model_.chart_placement(centre * turn.transpose());
    residual(*w, qc, u, w->rm, w->pm);
    dR_dw.col(l).head(sn) = Eigen::Map<const VecX>(w->rp.data(), sn) - Eigen::Map<const VecX>(w->rm.data(), sn);
    dR_dw.col(l).tail(n) = w->pp - w->pm;
  }
  dR_dw /= 2 * kCentralStep;
  w->res.chart_placement = placement;

  const Eigen::PartialPivLU<MatX> lu(Jq.topRightCorner(sn, sn));
  const double scale = Jq.topRightCorner(sn, sn).cwiseAbs().maxCoeff();
  if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;

  // The end: its attitude R1 = C R(θ^s), its public momentum (R1^T p_x, E^-T p_θ, p_r).
  const Vec3 theta = qc.col(s).segment<3>(j);
  const Mat3 Rs = chart.rotation(theta), R1 = centre * Rs, E = chart.rates_to_omega(theta);
  const Eigen::PartialPivLU<Mat3> Et(E.transpose());
  const Vec3 p_lin1 = R1.transpose() * w->pn.head<3>(), w_ang = Et.solve(Vec3(w->pn.segment<3>(j)));
  Mat3 M;  // d(E^T) along dθ^s applied to E^-T p_θ: column k for dθ_k
  for (int k = 0; k < 3; ++k) M.col(k) = chart.rates_to_omega_rate(theta, Vec3::Unit(k)).transpose() * w_ang;
  const auto P_y = Jq.bottomRightCorner(n, sn);
  // Columns with residual derivative X (sn rows), direct p^{k+1} derivative Pd and centre turn Wc -> out (2n rows).
  auto propagate = [&](const MatX& X, const MatX& Pd, const MatX& Wc, MatX& out) {
    w->sol = -lu.solve(X);
    const auto ys = w->sol.bottomRows(n);
    const MatX dp = P_y * w->sol + Pd;
    out.resize(2 * n, X.cols());
    out.topRows(n) = ys;
    out.topRows(3) = R1.transpose() * ys.topRows(3);
    out.middleRows(j, 3) = E * ys.middleRows(j, 3) + Rs.transpose() * Wc;
    out.bottomRows(n) = dp;
    out.middleRows(n, 3) = R1.transpose() * dp.topRows(3) + hat(p_lin1) * out.middleRows(j, 3);
    out.middleRows(n + j, 3) = Et.solve(dp.middleRows(j, 3) - M * ys.middleRows(j, 3));
  };
  if (A) {
    // Inputs (δv, δω, δr, δp): q^{k,0}'s position moves by C δv, the centre by δω, the joints by δr;
    // the chart momentum p^k = diag(C, E(0)^T, 1) p with C turning: d(C p_v) = -C p̂_v δω.
    const auto Jq0 = Jq.topLeftCorner(sn, n), P0 = Jq.bottomLeftCorner(n, n);
    MatX X = MatX::Zero(sn, 2 * n), Pd = MatX::Zero(n, 2 * n), Wc = MatX::Zero(3, 2 * n);
    X.leftCols(3) = Jq0.leftCols(3) * centre;
    Pd.leftCols(3) = P0.leftCols(3) * centre;
    X.middleCols(j, 3) = dR_dw.topRows(sn);
    X.block(0, j, 3, 3) -= centre * hat(Vec3(centre.transpose() * p0.head<3>()));
    Pd.middleCols(j, 3) = dR_dw.bottomRows(n);
    Wc.middleCols(j, 3).setIdentity();
    X.middleCols(j + 3, nr) = Jq0.middleCols(j + 3, nr);
    Pd.middleCols(j + 3, nr) = P0.middleCols(j + 3, nr);
    X.block(0, n, 3, 3) = centre;
    X.block(j, n + j, 3, 3) = chart.rates_to_omega(Vec3::Zero()).transpose();
    X.block(j + 3, n + j + 3, nr, nr).setIdentity();
    propagate(X, Pd, Wc, *A);
  }
  if (B) {
    if (want_u) {
      propagate(Ju.topRows(sn), Ju.bottomRows(n), MatX::Zero(3, S1 * m), *B);
    } else {
      B->setZero(2 * n, S1 * m);
    }
  }
  return true;
}

}  // namespace hovi
