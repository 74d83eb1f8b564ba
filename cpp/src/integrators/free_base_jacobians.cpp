#include "hovi/integrators/free_base_jacobians.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

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

  // The chart's rows of r^{k,0} gain the centre term's derivative. With Y' = 0 at the ends,
  //   C = sum_b Y'_b^T r^b + sum_a w^a dt D_a^T P_a,  D_a = Ẏ'_a - sum_b b^{ab} Y'_b / dt
  // (rotation_chart.hpp; r^b the interior DEL rows, P_a the chart joints' dL/dq̇), so that dC comes
  // from the rows of Jq and Ju, dP_a = Kvq(a) dq^a + sum_c b^{ac} / dt Kvv(a) dq^c, and A's derivatives.
  const auto th = qc.middleRows(j, 3);
  const MatX thd = th * quad_.b.transpose() / dt_;
  const MatX P = w->res.chart_P;
  std::vector<Mat3> Y(S1, Mat3::Zero()), D(S1);
  for (int b = 1; b < s; ++b) Y[b] = chart.centre_shift(th.col(b)) - Mat3::Identity();
  const Mat3 end = chart.centre_shift(th.col(s)) - Mat3::Identity();
  for (int a = 0; a < S1; ++a) {
    D[a] = chart.centre_shift_rate(th.col(a), thd.col(a)) - quad_.b(a, s) * end / dt_;
    for (int b = 1; b < s; ++b) D[a] -= quad_.b(a, b) * Y[b] / dt_;
  }
  MatX dC = MatX::Zero(3, S1 * n);
  for (int b = 1; b < s; ++b) dC.noalias() += Y[b].transpose() * Jq.block(b * n + j, 0, 3, S1 * n);
  for (int a = 0; a < S1; ++a) {
    dC.block(0, a * n, 3, n).noalias() += (quad_.w[a] * dt_) * D[a].transpose() * w->jac.Kvq[a].middleRows(j, 3);
    for (int c = 0; c < S1; ++c)
      if (quad_.b(a, c) != 0)
        dC.block(0, c * n, 3, n).noalias() += (quad_.w[a] * quad_.b(a, c)) * D[a].transpose() * w->jac.Kvv[a].middleRows(j, 3);
  }
  // the chart's own columns: Y' and D move with θ (A's second derivative by central differences of its closed form)
  for (int c = 0; c < S1; ++c)
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = Vec3::Unit(k);
      const Mat3 dA = chart.centre_shift_rate(th.col(c), e);  // dA(θ^c)/dθ_k
      const Vec3 tp = th.col(c) + kCentralStep * e, tm = th.col(c) - kCentralStep * e;
      const Mat3 dAdot = (chart.centre_shift_rate(tp, thd.col(c)) - chart.centre_shift_rate(tm, thd.col(c))) /
                         (2 * kCentralStep);  // d/dθ_k of Ȧ(θ^c, θ̇^c) at fixed θ̇
      Vec3 col = Vec3::Zero();
      if (c > 0 && c < s) col += dA.transpose() * w->r.col(c).segment<3>(j);
      for (int a = 0; a < S1; ++a) {
        Mat3 dD = (quad_.b(a, c) / dt_) * chart.centre_shift_rate(th.col(a), e);
        if (a == c) dD += dAdot;
        if (c == s) dD -= (quad_.b(a, s) / dt_) * dA;
        if (c > 0 && c < s) dD -= (quad_.b(a, c) / dt_) * dA;
        col += (quad_.w[a] * dt_) * dD.transpose() * P.col(a);
      }
      dC.col(c * n + j + k) += col;
    }
  Jq.block(j, 0, 3, S1 * n) += dC;
  if (want_u) {
    MatX dCu = MatX::Zero(3, S1 * m);
    for (int b = 1; b < s; ++b) dCu.noalias() += Y[b].transpose() * Ju.block(b * n + j, 0, 3, S1 * m);
    Ju.block(j, 0, 3, S1 * m) += dCu;
  }
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
