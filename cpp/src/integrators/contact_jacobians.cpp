#include "hovi/integrators/contact_jacobians.hpp"

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <functional>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

namespace {
constexpr double kStickTol = 1e-12;  // m: a sliding displacement γ this small over the step is a stick (round-off)
}

ContactJacobians::ContactJacobians(const Model& model, const Quadrature& quad, double dt, const ContactModel& contacts,
                                   const FreeBaseJacobians* free)
    : model_(model), quad_(quad), dt_(dt), contacts_(contacts), free_(free),
      pool_([this] { return std::make_unique<Workspace>(model_, quad_); }) {
  r_com_ = contacts.points_in_com_frames(model);
  // The tangent axes: x and/or y, those the friction directions (horizontal) reach.
  const bool x = contacts.D.col(0).cwiseAbs().maxCoeff() > 0, y = contacts.D.col(1).cwiseAbs().maxCoeff() > 0;
  T_.setZero(int(x) + int(y), 3);
  if (x) T_(0, 0) = 1;
  if (y) T_(int(x), 1) = 1;
}

void ContactJacobians::point_kinematics(Workspace& w, const Eigen::Ref<const MatX>& qc,
                                         const Eigen::Ref<const MatX>& u, const Eigen::Ref<const VecX>& z,
                                         bool want_u, const Mat3* centre) const {
  const int n = model_.n(), s = quad_.s, C = contacts_.size();
  w.Jq.resize((s + 1) * n, (s + 1) * n);
  if (centre) w.ws.data.chart_placement = w.data.chart_placement = w.res.chart_placement = model_.chart_placement(*centre);
  del_jacobian(model_, quad_, w.ws, qc, u, dt_, w.Jq, want_u ? &w.Ju : nullptr);
  if (centre) {
    w.r.resize(n, s);
    w.pn.resize(n);
    del_residual(model_, quad_, w.res, qc, VecX::Zero(n), u, dt_, w.r, w.pn);
    add_centre_term_jacobian(model_, quad_, dt_, qc, w.r, MatX(w.res.chart_P), w.ws, w.Jq, want_u ? &w.Ju : nullptr);
  }
  w.J0.setZero(3 * C, n);
  w.Je.setZero(3 * C, n);
  w.H.setZero(n, n);
  w.X0.resize(3, C);
  w.Xe.resize(3, C);
  const KinematicsView kin{model_, w.data.g.data(), w.data.Sbar.data(), 1};
  forward_kinematics(model_, w.data, qc.col(0));
  for (int c = 0; c < C; ++c) {
    Vec3 x;
    body_point_jacobian(kin, contacts_.points[c].body, r_com_.col(c), x, w.J0.middleRows(3 * c, 3));
    w.X0.col(c) = x;
    body_point_force_derivative(kin, contacts_.points[c].body, r_com_.col(c), contacts_.world_impulse(z, c), w.H);
  }
  forward_kinematics(model_, w.data, qc.col(s));
  for (int c = 0; c < C; ++c) {
    Vec3 x;
    body_point_jacobian(kin, contacts_.points[c].body, r_com_.col(c), x, w.Je.middleRows(3 * c, 3));
    w.Xe.col(c) = x;
  }
}

bool ContactJacobians::step_maps(Workspace& w, int ny, const std::function<bool(const MatX&, MatX&)>& solve, MatX* A,
                                  MatX* B, const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                                  const Eigen::Ref<const VecX>& z, const Mat3* centre) const {
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), sn = s * n;
  const auto P_y = w.Jq.bottomRightCorner(n, sn);  // dp^{k+1}/dy; p^{k+1} carries no impulse
  MatX rhs_u;
  if (B && m > 0) {
    rhs_u.setZero(ny, S1 * m);
    for (int a = 0; a < S1; ++a) rhs_u.block(0, a * m, sn, m) = w.Ju.block(0, a * m, sn, m);
  }
  if (centre) return tangent_maps(w, ny, solve, A, B, qc, u, z, *centre, rhs_u);
  if (A) {
    if (!solve(w.rhs, w.sol)) return false;
    A->resize(2 * n, 2 * n);
    A->topRows(n) = w.sol.middleRows(sn - n, n);
    A->bottomRows(n).noalias() = P_y * w.sol.topRows(sn);
    A->bottomLeftCorner(n, n) += w.Jq.bottomLeftCorner(n, n);
  }
  if (B) {
    B->setZero(2 * n, S1 * m);
    if (m > 0) {
      if (!solve(rhs_u, w.sol)) return false;
      B->topRows(n) = w.sol.middleRows(sn - n, n);
      B->bottomRows(n).noalias() = P_y * w.sol.topRows(sn);
      for (int a = 0; a < S1; ++a) B->block(n, a * m, n, m) += w.Ju.block(sn, a * m, n, m);
    }
  }
  return true;
}

bool ContactJacobians::tangent_maps(Workspace& w, int ny, const std::function<bool(const MatX&, MatX&)>& solve,
                                     MatX* A, MatX* B, const Eigen::Ref<const MatX>& qc,
                                     const Eigen::Ref<const MatX>& u, const Eigen::Ref<const VecX>& z,
                                     const Mat3& centre, const MatX& rhs_u) const {
  const int n = model_.n(), s = quad_.s, S1 = s + 1, m = model_.n_controls(), sn = s * n, j = model_.rotation_chart;
  const int C = contacts_.size();
  const auto P_y = w.Jq.bottomRightCorner(n, sn);
  VecX F(3 * C);  // the knot's world impulses
  for (int c = 0; c < C; ++c) F.segment<3>(3 * c) = contacts_.world_impulse(z, c);
  const VecX p0 = -(w.r.col(0) + w.J0.transpose() * F);  // r^{k,0} = p^k + ... + J_c(q^k)^T F_c = 0
  const TangentStep step(free_->base(), centre, qc, p0, w.pn);
  if (A) {
    // R's derivative by the centre's turn: the DEL rows (with the knot's impulses) and p^{k+1} by central
    // differences; a contact row through the points it moves, dq^a = A(θ^a) E(0)^-1 δω (θ^{k,0} = 0).
    const KinematicsView kin{model_, w.data.g.data(), w.data.Sbar.data(), 1};
    MatX Jc(3, n);
    const std::function<VecX(const SE3&)> knot = [&](const SE3& placement) {
      w.data.chart_placement = placement;
      forward_kinematics(model_, w.data, qc.col(0));
      VecX f = VecX::Zero(n);
      for (int c = 0; c < C; ++c) {
        Vec3 x;
        Jc.setZero();
        body_point_jacobian(kin, contacts_.points[c].body, r_com_.col(c), x, Jc);
        f.noalias() += Jc.transpose() * F.segment<3>(3 * c);
      }
      return f;
    };
    MatX dR_dw;
    free_->turn_derivative(w.res, qc, u, centre, &knot, dR_dw);
    const RotationChart& chart = free_->base().chart;
    const Mat3 E0inv = chart.rates_to_omega(Vec3::Zero()).inverse();
    const Mat3 end = chart.centre_shift(qc.col(s).segment<3>(j)) * E0inv;
    MatX d_turn = MatX::Zero(ny, 3);
    d_turn.topRows(sn) = dR_dw.topRows(sn);
    d_turn.bottomRows(ny - sn) = w.K.block(sn, sn - n + j, ny - sn, 3) * end + w.rhs.block(sn, j, ny - sn, 3) * E0inv;
    if (!solve(step.inputs(w.rhs.leftCols(n), d_turn, true), w.sol)) return false;
    const MatX Pd = step.inputs(w.Jq.bottomLeftCorner(n, n), dR_dw.bottomRows(n), false);
    step.outputs(w.sol.middleRows(sn - n, n), P_y * w.sol.topRows(sn) + Pd, step.turn(), *A);
  }
  if (B) {
    if (m == 0) {
      B->setZero(2 * n, 0);
      return true;
    }
    if (!solve(rhs_u, w.sol)) return false;
    MatX dp = P_y * w.sol.topRows(sn);
    for (int a = 0; a < S1; ++a) dp.middleCols(a * m, m) += w.Ju.block(sn, a * m, n, m);
    step.outputs(w.sol.middleRows(sn - n, n), dp, MatX::Zero(3, S1 * m), *B);
  }
  return true;
}

bool ContactJacobians::step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                                       const Eigen::Ref<const VecX>& z, MatX* A, MatX* B, const Mat3* centre) const {
  auto w = pool_.acquire();
  const int n = model_.n(), s = quad_.s, sn = s * n;
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), nt = static_cast<int>(T_.rows());
  point_kinematics(*w, qc, u, z, B != nullptr && model_.n_controls() > 0, centre);
  const MatX &Jq = w->Jq, &J0 = w->J0, &Je = w->Je;
  MatX &K = w->K, &rhs = w->rhs;
  int ny = sn;
  std::vector<int> column(C, -1);  // the first unknown of each contact with a normal impulse
  std::vector<char> stick(C, 0);
  for (int c = 0; c < C; ++c) {
    const auto zc = z.segment(c * pc, pc);
    if (zc[0] > 0) {
      column[c] = ny;
      stick[c] = zc[d + 1] <= kStickTol;
      ny += stick[c] ? 1 + nt : 1;
    }
  }
  // dR/dy: the DEL rows with the impulses' columns, then per contact its gap and stick rows.
  K.setZero(ny, ny);
  K.topLeftCorner(sn, sn) = Jq.topRightCorner(sn, sn);
  for (int c = 0, row = sn; c < C; ++c) {
    if (column[c] < 0) continue;
    const auto zc = z.segment(c * pc, pc);
    const auto J0c = J0.middleRows(3 * c, 3), Jec = Je.middleRows(3 * c, 3);
    Vec3 normal = Vec3::UnitZ();
    if (!stick[c]) normal += contacts_.mu * contacts_.D.transpose() * zc.segment(1, d) / zc.segment(1, d).sum();
    K.block(0, column[c], n, 1) = J0c.transpose() * normal;
    K.block(row, sn - n, 1, n) = Jec.row(2);  // dφ_c/dq^{k+1}
    ++row;
    if (stick[c]) {
      K.block(0, column[c] + 1, n, nt) = J0c.transpose() * T_.transpose();
      K.block(row, sn - n, nt, n) = T_ * Jec;  // d(T x_c(q^{k+1}))/dq^{k+1}
      row += nt;
    }
  }
  // Redundant contacts held (three or four corners of a sole, 9 rows on a foot's 6 freedoms) leave
  // the impulses undetermined but not the motion: then the least-norm solution, whose y part is
  // the unique one if the rows are consistent (checked on the residual).
  const Eigen::PartialPivLU<MatX> lu(K);
  const double scale = K.cwiseAbs().maxCoeff();
  const bool regular = lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-12 * scale;
  Eigen::CompleteOrthogonalDecomposition<MatX> cod;
  if (!regular) {
    cod.setThreshold(1e-12);
    cod.compute(K);
  }
  auto solve = [&](const MatX& b, MatX& x) {
    x = regular ? MatX(-lu.solve(b)) : MatX(-cod.solve(b));
    return (K * x + b).cwiseAbs().maxCoeff() <= 1e-9 * (1 + b.cwiseAbs().maxCoeff()) * (1 + scale);
  };
  if (A) {
    rhs.setZero(ny, 2 * n);
    rhs.topLeftCorner(sn, n) = Jq.topLeftCorner(sn, n);
    rhs.topLeftCorner(n, n) += w->H;
    rhs.block(0, n, n, n).setIdentity();
    for (int c = 0, row = sn; c < C; ++c) {  // the stick rows' -T dx_c(q^k)/dq^k
      if (column[c] < 0) continue;
      ++row;
      if (stick[c]) {
        rhs.block(row, 0, nt, n) = -T_ * J0.middleRows(3 * c, 3);
        row += nt;
      }
    }
  }
  return step_maps(*w, ny, solve, A, B, qc, u, z, centre);
}

bool ContactJacobians::smoothed_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                                           const Eigen::Ref<const VecX>& z, double smoothing, MatX* A, MatX* B,
                                           const Mat3* centre) const {
  auto w = pool_.acquire();
  const int n = model_.n(), s = quad_.s, sn = s * n;
  const int C = contacts_.size(), d = contacts_.d(), pc = contacts_.per_contact(), nz = contacts_.unknowns();
  const int ny = sn + nz;
  point_kinematics(*w, qc, u, z, B != nullptr && model_.n_controls() > 0, centre);
  const MatX &Jq = w->Jq, &J0 = w->J0, &Je = w->Je, &H = w->H, &X0 = w->X0, &Xe = w->Xe;
  MatX &K = w->K, &rhs = w->rhs;
  // Each pair in impulse units: a complement w_i (a gap or displacement, m) over its impulse's own
  // mobility (m per N s: the displacement of the contact point along its direction per unit impulse
  // there, through the step), so that the central path weighs both sides of a switch by their
  // physics, not by their units; the cone pair's γ (m) likewise.
  const Eigen::PartialPivLU<MatX> luy(Jq.topRightCorner(sn, sn));
  MatX G = MatX::Zero(sn, 3 * C);
  G.topRows(n) = J0.transpose();
  const MatX W3e = (-luy.solve(G)).middleRows(sn - n, n);
  VecX mobility(nz);
  for (int c = 0; c < C; ++c) {
    const Mat3 Kc = Je.middleRows(3 * c, 3) * W3e.middleCols(3 * c, 3);  // 3 x 3: point motion per impulse
    mobility[c * pc] = Kc(2, 2);
    double friction = 0;
    for (int i = 0; i < d; ++i) {
      const Vec3 Di = contacts_.D.row(i).transpose();
      mobility[c * pc + 1 + i] = Di.dot(Kc * Di);
      friction = std::max(friction, mobility[c * pc + 1 + i]);
    }
    mobility[c * pc + d + 1] = friction;  // the cone pair: γ (m) over the friction's mobility
  }
  for (int i = 0; i < nz; ++i)
    if (!(mobility[i] > 0)) mobility[i] = mobility.cwiseAbs().maxCoeff() > 0 ? mobility.cwiseAbs().maxCoeff() : 1.0;
  // dR/d(y, z): the DEL rows with every impulse's column, then one smoothed row per pair.
  K.setZero(ny, ny);
  K.topLeftCorner(sn, sn) = Jq.topRightCorner(sn, sn);
  rhs.setZero(ny, 2 * n);  // d/d(q^k, p^k)
  rhs.topLeftCorner(sn, n) = Jq.topLeftCorner(sn, n);
  rhs.topLeftCorner(n, n) += H;
  rhs.block(0, n, n, n).setIdentity();
  for (int c = 0; c < C; ++c) {
    const int base = c * pc, row = sn + base;
    const auto zc = z.segment(base, pc);
    const auto J0c = J0.middleRows(3 * c, 3), Jec = Je.middleRows(3 * c, 3);
    K.block(0, sn + base, n, 1) = J0c.row(2).transpose();                          // λ along +z
    K.block(0, sn + base + 1, n, d) = J0c.transpose() * contacts_.D.transpose();    // β along D_i
    const double h = contacts_.surface(c, Xe.col(c));
    const Vec3 disp = Xe.col(c) - X0.col(c);
    // the complements w and their derivatives: gap row, friction rows, cone row
    for (int i = 0; i < pc; ++i) {
      double wi;
      Eigen::RowVectorXd dw_dyend = Eigen::RowVectorXd::Zero(n), dw_dq0 = Eigen::RowVectorXd::Zero(n);
      Eigen::RowVectorXd dw_dz = Eigen::RowVectorXd::Zero(nz);
      if (i == 0) {
        wi = Xe(2, c) - h;
        dw_dyend = Jec.row(2);
      } else if (i <= d) {
        const Eigen::RowVector3d Di = contacts_.D.row(i - 1);
        wi = zc[d + 1] + Di.dot(disp);
        dw_dyend = Di * Jec;
        dw_dq0 = -Di * J0c;
        dw_dz[base + d + 1] = 1;
      } else {
        wi = contacts_.mu * zc[0] - zc.segment(1, d).sum();
        dw_dz[base] = contacts_.mu;
        dw_dz.segment(base + 1, d).setConstant(-1);
      }
      // in impulse units (N s): the cone pair's z (γ, m) and the other pairs' w (m) over the mobility
      const double mi = mobility[base + i], zs = i == d + 1 ? 1 / mi : 1.0, ws = i == d + 1 ? 1.0 : 1 / mi;
      const double zi = zs * zc[i], wsc = ws * wi;
      // the central path through (zi, w): (z + δ)(w + δ) = smoothing, δ >= 0
      const double delta = std::max(0.0, 0.5 * (-(zi + wsc) + std::sqrt((zi - wsc) * (zi - wsc) + 4 * smoothing)));
      const double zt = zi + delta, wt = wsc + delta;
      // wt d(zs z_i) + zt d(ws w_i) = 0
      K.block(row + i, sn - n, 1, n) = (zt * ws) * dw_dyend;
      K.block(row + i, sn, 1, nz) = (zt * ws) * dw_dz;
      K(row + i, sn + base + i) += wt * zs;
      rhs.block(row + i, 0, 1, n) = (zt * ws) * dw_dq0;
    }
  }
  const Eigen::PartialPivLU<MatX> lu(K);
  const double scale = K.cwiseAbs().maxCoeff();
  if (!(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;
  return step_maps(*w, ny, [&](const MatX& b, MatX& x) { x = -lu.solve(b); return true; }, A, B, qc, u, z, centre);
}

}  // namespace hovi
