#include "hovi/trajopt/hermite_simpson_transcription.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/errors.hpp"
#include "hovi/trajopt/jacobian_blocks.hpp"

namespace hovi {

namespace {
// The collocation rows of one interval: row r = sum_p cq[r][p] q_p + h cv[r][p] v_p + h ca[r][p] a_p
// over its points p = 0 (knot), 1 (midpoint), 2 (next knot).
constexpr double kCq[4][3] = {{-0.5, 1, -0.5}, {0, 0, 0}, {-1, 0, 1}, {0, 0, 0}};
constexpr double kCv[4][3] = {{-1.0 / 8, 0, 1.0 / 8}, {-0.5, 1, -0.5}, {-1.0 / 6, -4.0 / 6, -1.0 / 6}, {-1, 0, 1}};
constexpr double kCa[4][3] = {{0, 0, 0}, {-1.0 / 8, 0, 1.0 / 8}, {0, 0, 0}, {-1.0 / 6, -4.0 / 6, -1.0 / 6}};
// cv of rows 0 and 2 and ca are multiplied by h; cv of rows 1 and 3 are plain coefficients.
double cv(int r, int p, double h) { return (r == 0 || r == 2) ? h * kCv[r][p] : kCv[r][p]; }
double ca(int r, int p, double h) { return h * kCa[r][p]; }

Model constraint_forces_only(const Model& model) {
  Model geometry = model;
  geometry.joint_forces = JointForces();
  geometry.joint_forces.resize(model.n());
  geometry.wrenches.clear();
  return with_constraint_forces(geometry);
}
}  // namespace

HermiteSimpsonTranscription::Workspace::Workspace(const Model& model, const Model& aug, const Model& geometry)
    : data(model), forces(aug), hessian(geometry), rnea(model) {}

HermiteSimpsonTranscription::HermiteSimpsonTranscription(const Model& model, int N, double dt, ControlMode controls,
                                                         bool implicit)
    : model_(model), aug_(with_constraint_forces(model)), geometry_(constraint_forces_only(model)), N_(N),
      n_(model.n()), m_(model.n_controls()), mc_(model.n_constraints()), dt_(dt), controls_(controls),
      implicit_(implicit), pool_([this] { return std::make_unique<Workspace>(model_, aug_, geometry_); }) {
  model.refuse_free_base("trajectory optimisation");
  if (n_ == 0) throw ModelError("the model has no joints");
  if (N < 1) throw InputError("the number of stages N must be at least 1, got " + std::to_string(N));
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite, got " + std::to_string(dt));
  const int P = n_points();
  n_variables_ = lambda_offset() + P * mc_;
  dyn_row_ = 4 * N_ * n_;
  con_row_ = dyn_row_ + (implicit_ ? P * n_ : 0);
  n_rows_ = con_row_ + (mc_ ? (P + 2) * mc_ : 0);
  build_structure();
}

int HermiteSimpsonTranscription::u_index(int i) const {
  return u_offset() + (controls_ == ControlMode::PerPoint ? i : std::min(i / 2, N_ - 1)) * m_;
}

void HermiteSimpsonTranscription::build_structure() {
  const int n = n_, m = m_, mc = mc_;
  BlockStructure b;
  for (int k = 0; k < N_; ++k)
    for (int r = 0; r < 4; ++r) {
      const int row = (4 * k + r) * n;
      std::vector<int> ucols;  // distinct control columns of the row block (held controls repeat)
      for (int p = 0; p < 3; ++p) {
        const int i = 2 * k + p;
        const bool dense = !implicit_ && kCa[r][p] != 0;
        if (dense) {
          b.dense(row, q_offset() + i * n, n, n);
          b.dense(row, v_offset() + i * n, n, n);
          if (mc) b.dense(row, lambda_offset() + i * mc, n, mc);
          if (m && std::find(ucols.begin(), ucols.end(), u_index(i)) == ucols.end()) ucols.push_back(u_index(i));
          continue;
        }
        if (kCq[r][p] != 0) b.diagonal(row, q_offset() + i * n, n);
        if (kCv[r][p] != 0) b.diagonal(row, v_offset() + i * n, n);
        if (implicit_ && kCa[r][p] != 0) b.diagonal(row, a_offset() + i * n, n);
      }
      for (int c : ucols) b.dense(row, c, n, m);
    }
  for (int i = 0; implicit_ && i < n_points(); ++i) {
    const int row = dyn_row_ + i * n;
    b.dense(row, q_offset() + i * n, n, n);
    b.dense(row, v_offset() + i * n, n, n);
    b.dense(row, a_offset() + i * n, n, n);
    if (m) b.dense(row, u_index(i), n, m);
    if (mc) b.dense(row, lambda_offset() + i * mc, n, mc);
  }
  if (mc) {
    for (int i = 0; i < n_points(); ++i) {
      const int row = con_row_ + i * mc;
      b.dense(row, q_offset() + i * n, mc, n);
      b.dense(row, v_offset() + i * n, mc, n);
      if (implicit_) {
        b.dense(row, a_offset() + i * n, mc, n);
      } else {
        if (m) b.dense(row, u_index(i), mc, m);
        b.dense(row, lambda_offset() + i * mc, mc, mc);
      }
    }
    const int row = con_row_ + n_points() * mc;
    b.dense(row, q_offset(), mc, n);       // h(q_0)
    b.dense(row + mc, q_offset(), mc, n);  // Dh(q_0) v_0
    b.dense(row + mc, v_offset(), mc, n);
  }
  structure_ = b.finish();
}

void HermiteSimpsonTranscription::inputs(const Eigen::Ref<const VecX>& x, int i, Workspace& ws, VecX& q, VecX& v,
                                         VecX& a) const {
  q = x.segment(q_offset() + i * n_, n_);
  v = x.segment(v_offset() + i * n_, n_);
  if (implicit_) a = x.segment(a_offset() + i * n_, n_);
  ws.w.resize(m_ + mc_);
  if (m_) ws.w.head(m_) = x.segment(u_index(i), m_);
  if (mc_) ws.w.tail(mc_) = x.segment(lambda_offset() + i * mc_, mc_);
}

void HermiteSimpsonTranscription::evaluate_point(const Eigen::Ref<const VecX>& x, int i, bool derivatives,
                                                 Workspace& ws, Point& pt) const {
  VecX q, v;
  inputs(x, i, ws, q, v, pt.a);
  ForceJacobians& f = ws.forces;
  force_jacobians(aug_, ws.data, q, v, ws.w, f, derivatives);  // Q = joint forces + wrenches + Dh^T λ
  if (implicit_) {
    if (!derivatives) {
      pt.tau = inverse_dynamics(model_, ws.data, q, v, pt.a) - f.Q;
      return;
    }
    rnea_derivatives(model_, ws.data, q, v, pt.a, ws.rnea);
    pt.tau = ws.rnea.tau - f.Q;
    pt.dq = ws.rnea.dq - f.Qq;
    pt.dv = ws.rnea.dv - f.Qv;
    pt.dw = -f.Qu;
    pt.M = ws.rnea.M;
    return;
  }
  // Explicit: a = M^{-1} (Q - ID(q, v, 0)), and da/d(q, v, w) = -M^{-1} d(ID - Q)/d(q, v, w) at that a.
  const VecX bias = inverse_dynamics(model_, ws.data, q, v, VecX::Zero(n_));
  pt.M = mass_matrix(model_, ws.data, q);
  const Eigen::LLT<MatX> llt(pt.M);
  pt.a = llt.solve(f.Q - bias);
  if (!derivatives) return;
  rnea_derivatives(model_, ws.data, q, v, pt.a, ws.rnea);
  pt.dq = -llt.solve(ws.rnea.dq - f.Qq);
  pt.dv = -llt.solve(ws.rnea.dv - f.Qv);
  // (an empty right-hand side, no controls or multipliers, must not reach Eigen's triangular solve:
  // it takes a reference to element (0, 0), undefined behaviour found by make sanitize)
  if (f.Qu.cols() > 0) pt.dw = llt.solve(f.Qu);
  else pt.dw.resize(n_, 0);
}

void HermiteSimpsonTranscription::hessian_times(const VecX& q, const VecX& v, Workspace& ws, MatX& Hv) const {
  Hv.resize(mc_, n_);
  VecX e = VecX::Zero(mc_);
  const VecX zero = VecX::Zero(n_);
  for (int c = 0; c < mc_; ++c) {
    e.setZero();
    e[c] = 1;
    force_jacobians(geometry_, ws.data, q, zero, e, ws.hessian, false);  // Q = ∇h_c, Qq = ∇²h_c
    Hv.row(c) = (ws.hessian.Qq * v).transpose();
  }
}

void HermiteSimpsonTranscription::constraint_acceleration(const VecX& q, const VecX& v, const VecX& a, Workspace& ws,
                                                          VecX& value, MatX* Jq, MatX* Jv) const {
  MatX Hv, Ha, Hp, Hm;
  hessian_times(q, v, ws, Hv);
  forward_kinematics(model_, ws.data, q);
  ws.Dh.resize(mc_, n_);
  constraint_jacobian(model_, KinematicsView{model_, ws.data.g.data(), ws.data.Sbar.data(), 1}, ws.Dh);
  value = ws.Dh * a + Hv * v;  // ḧ = Dh a + v^T ∇²h v
  if (!Jq) return;
  hessian_times(q, a, ws, Ha);
  Jq->resize(mc_, n_);
  VecX qp = q, qm = q;
  for (int k = 0; k < n_; ++k) {  // d/dq (v^T ∇²h(q) v): central differences of the exact Hessian product
    const double eps = 1e-6 * (1 + std::abs(q[k]));
    qp[k] = q[k] + eps;
    qm[k] = q[k] - eps;
    hessian_times(qp, v, ws, Hp);
    hessian_times(qm, v, ws, Hm);
    Jq->col(k) = Ha.col(k) + (Hp * v - Hm * v) / (2 * eps);
    qp[k] = qm[k] = q[k];
  }
  *Jv = 2 * Hv;  // ws.Dh still holds Dh(q): the differences above change only ws.data
}

void HermiteSimpsonTranscription::constraints(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> g) const {
  if (x.size() != n_variables_ || g.size() != n_rows_) throw InputError("constraints: x or g has the wrong size");
  const int n = n_, P = n_points();
  auto ws = pool_.acquire();
  std::vector<VecX> a(P);
  VecX q, v, value;
  Point pt;
  for (int i = 0; i < P; ++i) {
    evaluate_point(x, i, false, *ws, pt);
    a[i] = pt.a;
    if (implicit_) g.segment(dyn_row_ + i * n, n) = pt.tau;
  }
  for (int k = 0; k < N_; ++k)
    for (int r = 0; r < 4; ++r) {
      auto row = g.segment((4 * k + r) * n, n);
      row.setZero();
      for (int p = 0; p < 3; ++p) {
        const int i = 2 * k + p;
        row += kCq[r][p] * x.segment(q_offset() + i * n, n) + cv(r, p, dt_) * x.segment(v_offset() + i * n, n) +
               ca(r, p, dt_) * a[i];
      }
    }
  if (!mc_) return;
  for (int i = 0; i < P; ++i) {
    inputs(x, i, *ws, q, v, value);
    constraint_acceleration(q, v, a[i], *ws, value, nullptr, nullptr);
    g.segment(con_row_ + i * mc_, mc_) = value;
  }
  q = x.segment(q_offset(), n);
  forward_kinematics(model_, ws->data, q);
  const KinematicsView kin{model_, ws->data.g.data(), ws->data.Sbar.data(), 1};
  ws->h.resize(mc_);
  constraint_values(model_, kin, q, ws->h);
  ws->Dh.resize(mc_, n);
  constraint_jacobian(model_, kin, ws->Dh);
  g.segment(con_row_ + P * mc_, mc_) = ws->h;
  g.segment(con_row_ + (P + 1) * mc_, mc_) = ws->Dh * x.segment(v_offset(), n);
}

void HermiteSimpsonTranscription::jacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> values) const {
  if (x.size() != n_variables_ || values.size() != structure_.nnz())
    throw InputError("jacobian: x or values has the wrong size");
  const int n = n_, m = m_, mc = mc_, P = n_points();
  auto ws = pool_.acquire();
  std::vector<Point> pts(P);
  for (int i = 0; i < P; ++i) evaluate_point(x, i, true, *ws, pts[i]);
  const MatX I = MatX::Identity(n, n);
  int at = 0;
  for (int k = 0; k < N_; ++k)
    for (int r = 0; r < 4; ++r) {
      std::vector<std::pair<int, MatX>> ublocks;  // summed per distinct control column
      for (int p = 0; p < 3; ++p) {
        const int i = 2 * k + p;
        const double cq = kCq[r][p], cvv = cv(r, p, dt_), caa = ca(r, p, dt_);
        if (!implicit_ && kCa[r][p] != 0) {
          at = put_dense(values, at, cq * I + caa * pts[i].dq);
          at = put_dense(values, at, cvv * I + caa * pts[i].dv);
          if (mc) at = put_dense(values, at, caa * pts[i].dw.rightCols(mc));
          if (m) {
            auto it = std::find_if(ublocks.begin(), ublocks.end(), [&](const auto& e) { return e.first == u_index(i); });
            if (it == ublocks.end()) ublocks.emplace_back(u_index(i), caa * pts[i].dw.leftCols(m));
            else it->second += caa * pts[i].dw.leftCols(m);
          }
          continue;
        }
        if (cq != 0) at = put_diagonal(values, at, n, cq);
        if (kCv[r][p] != 0) at = put_diagonal(values, at, n, cvv);
        if (implicit_ && caa != 0) at = put_diagonal(values, at, n, caa);
      }
      for (const auto& e : ublocks) at = put_dense(values, at, e.second);
    }
  for (int i = 0; implicit_ && i < P; ++i) {
    at = put_dense(values, at, pts[i].dq);
    at = put_dense(values, at, pts[i].dv);
    at = put_dense(values, at, pts[i].M);
    if (m) at = put_dense(values, at, pts[i].dw.leftCols(m));
    if (mc) at = put_dense(values, at, pts[i].dw.rightCols(mc));
  }
  if (!mc) return;
  VecX q, v, a, value;
  MatX Jq, Jv;
  for (int i = 0; i < P; ++i) {
    inputs(x, i, *ws, q, v, a);
    constraint_acceleration(q, v, pts[i].a, *ws, value, &Jq, &Jv);
    if (implicit_) {
      at = put_dense(values, at, Jq);
      at = put_dense(values, at, Jv);
      at = put_dense(values, at, ws->Dh);
    } else {  // through a = FD(q, v, u, λ)
      at = put_dense(values, at, Jq + ws->Dh * pts[i].dq);
      at = put_dense(values, at, Jv + ws->Dh * pts[i].dv);
      if (m) at = put_dense(values, at, ws->Dh * pts[i].dw.leftCols(m));
      at = put_dense(values, at, ws->Dh * pts[i].dw.rightCols(mc));
    }
  }
  q = x.segment(q_offset(), n);
  v = x.segment(v_offset(), n);
  MatX Hv;
  hessian_times(q, v, *ws, Hv);
  forward_kinematics(model_, ws->data, q);
  constraint_jacobian(model_, KinematicsView{model_, ws->data.g.data(), ws->data.Sbar.data(), 1}, ws->Dh);
  at = put_dense(values, at, ws->Dh);  // h(q_0)
  at = put_dense(values, at, Hv);      // d(Dh v_0)/dq_0 = (∇²h v_0)^T
  at = put_dense(values, at, ws->Dh);
}

}  // namespace hovi
