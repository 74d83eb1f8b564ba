#include "hovi/trajopt/variational_transcription.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"
#include "hovi/trajopt/jacobian_blocks.hpp"
#include "hovi/util/central_differences.hpp"

namespace hovi {


VariationalTranscription::Workspace::Workspace(const Model& aug, const Model& model, const Quadrature& quad)
    : del(aug, quad), jac(aug, quad), hess(aug, quad), data(model) {}

VariationalTranscription::VariationalTranscription(const Model& model, int s, int N, double dt, ControlMode controls)
    : aug_(model.n_constraints() ? with_constraint_forces(model) : model), model_(model), quad_(s), N_(N),
      n_(model.n()), m_(model.n_controls()), mc_(model.n_constraints()), dt_(dt), controls_(controls),
      pool_([this] { return std::make_unique<Workspace>(aug_, model_, quad_); }) {
  if (n_ == 0) throw ModelError("the model has no joints");
  model.refuse_free_base("trajectory optimisation");
  if (N < 1) throw InputError("the number of stages N must be at least 1, got " + std::to_string(N));
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite, got " + std::to_string(dt));
  n_variables_ = lambda_offset() + N_ * s * mc_;
  n_rows_ = holonomic_row() + n_points() * mc_;
  build_structure();
  build_hessian_structure();
}

int VariationalTranscription::u_index(int k, int a) const {
  return u_offset() + (controls_ == ControlMode::PerPoint ? k * quad_.s + a : k) * m_;
}

void VariationalTranscription::build_structure() {
  const int s = quad_.s, S1 = s + 1, n = n_;
  BlockStructure b;
  for (int k = 0; k < N_; ++k) {
    const int r0 = k * S1 * n;
    b.dense(r0, q_offset() + k * s * n, S1 * n, S1 * n);           // d/dq^{k,0..s}
    b.diagonal(r0, p_offset() + k * n, n);                         // r^{k,0} = p^k + ...
    b.diagonal(r0 + s * n, p_offset() + (k + 1) * n, n);           // p^{k+1} - P
    for (int a = 0; a <= s && m_; ++a) b.dense(r0 + a * n, u_index(k, a), n, m_);
    for (int a = 0; a < s && mc_; ++a) b.dense(r0 + a * n, lambda_offset() + (k * s + a) * mc_, n, mc_);
  }
  for (int j = 0; j < n_points() && mc_; ++j) b.dense(holonomic_row() + j * mc_, q_offset() + j * n, mc_, n);
  structure_ = b.finish();
}

void VariationalTranscription::stage_inputs(const Eigen::Ref<const VecX>& x, int k, Workspace& w) const {
  const int s = quad_.s, n = n_;
  w.qc = Eigen::Map<const MatX>(x.data() + q_offset() + k * s * n, n, s + 1);
  w.u.setZero(m_ + mc_, s + 1);
  for (int a = 0; a <= s && m_; ++a) w.u.col(a).head(m_) = x.segment(u_index(k, a), m_);
  for (int a = 0; a < s && mc_; ++a) w.u.col(a).tail(mc_) = x.segment(lambda_offset() + (k * s + a) * mc_, mc_);
}

void VariationalTranscription::constraints(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> g) const {
  if (x.size() != n_variables_ || g.size() != n_rows_) throw InputError("constraints: x or g has the wrong size");
  const int s = quad_.s, S1 = s + 1, n = n_;
  auto w = pool_.acquire();
  w->r.resize(n, s);
  w->p_next.resize(n);
  for (int k = 0; k < N_; ++k) {
    stage_inputs(x, k, *w);
    del_residual(aug_, quad_, w->del, w->qc, x.segment(p_offset() + k * n, n), w->u, dt_, w->r, w->p_next);
    g.segment(k * S1 * n, s * n) = Eigen::Map<const VecX>(w->r.data(), s * n);
    g.segment(k * S1 * n + s * n, n) = x.segment(p_offset() + (k + 1) * n, n) - w->p_next;
  }
  w->h.resize(mc_);
  for (int j = 0; j < n_points() && mc_; ++j) {
    const auto q = x.segment(q_offset() + j * n, n);
    forward_kinematics(model_, w->data, q);
    constraint_values(model_, KinematicsView{model_, w->data.g.data(), w->data.Sbar.data(), 1}, q, w->h);
    g.segment(holonomic_row() + j * mc_, mc_) = w->h;
  }
}

void VariationalTranscription::jacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> values) const {
  if (x.size() != n_variables_ || values.size() != structure_.nnz())
    throw InputError("jacobian: x or values has the wrong size");
  const int s = quad_.s, S1 = s + 1, n = n_, ma = m_ + mc_;
  auto w = pool_.acquire();
  w->Jq.resize(S1 * n, S1 * n);
  int at = 0;
  for (int k = 0; k < N_; ++k) {
    stage_inputs(x, k, *w);
    del_jacobian(aug_, quad_, w->jac, w->qc, w->u, dt_, w->Jq, (m_ || mc_) ? &w->Ju : nullptr);
    w->Jq.bottomRows(n) *= -1;  // the momentum rows are p^{k+1} - P
    if (m_ || mc_) w->Ju.bottomRows(n) *= -1;
    at = put_dense(values, at, w->Jq);
    at = put_diagonal(values, at, 2 * n, 1.0);  // d r^{k,0}/dp^k and d(p^{k+1} - P)/dp^{k+1}
    for (int a = 0; a <= s && m_; ++a) at = put_dense(values, at, w->Ju.block(a * n, a * ma, n, m_));
    for (int a = 0; a < s && mc_; ++a) at = put_dense(values, at, w->Ju.block(a * n, a * ma + m_, n, mc_));
  }
  w->Dh.resize(mc_, n);
  for (int j = 0; j < n_points() && mc_; ++j) {
    forward_kinematics(model_, w->data, x.segment(q_offset() + j * n, n));
    constraint_jacobian(model_, KinematicsView{model_, w->data.g.data(), w->data.Sbar.data(), 1}, w->Dh);
    at = put_dense(values, at, w->Dh);
  }
}


std::vector<int> VariationalTranscription::stage_variables(int k, std::vector<int>& input_at) const {
  const int s = quad_.s, S1 = s + 1, n = n_, ma = m_ + mc_;
  std::vector<int> vars;
  for (int i = 0; i < S1 * n; ++i) vars.push_back(q_offset() + k * s * n + i);
  input_at.assign(S1 * ma, -1);
  for (int a = 0; a <= s; ++a)
    for (int r = 0; r < m_; ++r) {   // held controls: one variable for every point
      const int v = u_index(k, a) + r;
      const auto it = std::find(vars.begin() + S1 * n, vars.end(), v);
      input_at[a * ma + r] = static_cast<int>(it - vars.begin());
      if (it == vars.end()) vars.push_back(v);
    }
  for (int a = 0; a < s; ++a)
    for (int r = 0; r < mc_; ++r) {
      input_at[a * ma + m_ + r] = static_cast<int>(vars.size());
      vars.push_back(lambda_offset() + (k * s + a) * mc_ + r);
    }
  return vars;
}

void VariationalTranscription::build_hessian_structure() {
  std::vector<int> rows, cols;
  for (int k = 0; k < N_; ++k) {
    const std::vector<int> vars = stage_variables(k, input_at_);
    for (std::size_t i = 0; i < vars.size(); ++i)
      for (std::size_t j = 0; j <= i; ++j) {
        rows.push_back(vars[i]);
        cols.push_back(vars[j]);
      }
    stage_variables_ = static_cast<int>(vars.size());
  }
  stage_entries_ = stage_variables_ * (stage_variables_ + 1) / 2;
  for (int j = 0; j < n_points() && mc_; ++j)
    for (int i = 0; i < n_; ++i)
      for (int l = 0; l <= i; ++l) {
        rows.push_back(q_offset() + j * n_ + i);
        cols.push_back(q_offset() + j * n_ + l);
      }
  hessian_structure_.rows = Eigen::Map<Eigen::VectorXi>(rows.data(), static_cast<long>(rows.size()));
  hessian_structure_.cols = Eigen::Map<Eigen::VectorXi>(cols.data(), static_cast<long>(cols.size()));
}

void VariationalTranscription::holonomic_hessian(const Eigen::Ref<const VecX>& x, const Eigen::Ref<const VecX>& lambda,
                                                 int j, Workspace& w, Eigen::Ref<VecX> values) const {
  const int n = n_;
  const auto lam = lambda.segment(holonomic_row() + j * mc_, mc_);
  VecX q = x.segment(q_offset() + j * n, n);
  const auto gradient = [&](const VecX& qj, VecX& out) {   // Dh(q)^T lambda_h
    forward_kinematics(model_, w.data, qj);
    constraint_jacobian(model_, KinematicsView{model_, w.data.g.data(), w.data.Sbar.data(), 1}, w.Dh);
    out.noalias() = w.Dh.transpose() * lam;
  };
  if (lam.cwiseAbs().maxCoeff() != 0) hessian_by_central_differences(q, VecX::Ones(n), gradient, w.Hv, w.gp, w.g0, w.Hqq);
  else w.Hv.setZero(n, n);
  int at = 0;
  for (int i = 0; i < n; ++i)
    for (int l = 0; l <= i; ++l) values[at++] = w.Hv(i, l);
}

void VariationalTranscription::hessian(const Eigen::Ref<const VecX>& x, const Eigen::Ref<const VecX>& lambda,
                                       Eigen::Ref<VecX> values, int threads) const {
  if (x.size() != n_variables_ || lambda.size() != n_rows_ || values.size() != hessian_structure_.nnz())
    throw InputError("hessian: x, lambda or values has the wrong size");
  const int s = quad_.s, S1 = s + 1, n = n_, ma = m_ + mc_, V = stage_variables_;
  const auto stage = [&](int k, int) {
    auto w = pool_.acquire();
    stage_inputs(x, k, *w);
    w->nu.resize(n, S1);   // the multipliers of D_{a+1} L_d + F_d^{k,a}: the momentum rows are p^{k+1} - P
    for (int a = 0; a < s; ++a) w->nu.col(a) = lambda.segment(k * S1 * n + a * n, n);
    w->nu.col(s) = -lambda.segment(k * S1 * n + s * n, n);
    w->Hqq.resize(S1 * n, S1 * n);
    w->Huq.resize(S1 * ma, S1 * n);
    w->Huu.resize(S1 * ma, S1 * ma);
    del_hessian(aug_, quad_, w->hess, w->qc, w->u, w->nu, dt_, w->Hqq, w->Huq, w->Huu);
    w->Hv.setZero(V, V);
    w->Hv.topLeftCorner(S1 * n, S1 * n) = w->Hqq;
    for (int i = 0; i < S1 * ma; ++i) {
      const int pi = input_at_[i];
      if (pi < 0) continue;
      w->Hv.row(pi).head(S1 * n) += w->Huq.row(i);   // inputs come after the control points: lower triangle
      const int a = i / ma;
      for (int l = a * ma; l < (a + 1) * ma; ++l)
        if (input_at_[l] >= 0) w->Hv(pi, input_at_[l]) += w->Huu(i, l);
    }
    long at = static_cast<long>(k) * stage_entries_;
    for (int i = 0; i < V; ++i)
      for (int l = 0; l <= i; ++l) values[at++] = w->Hv(i, l);
  };
  const std::vector<std::string> errors = parallel_for(N_, std::max(1, threads), stage);
  for (const std::string& e : errors)
    if (!e.empty()) throw std::runtime_error("the transcription's Hessian failed: " + e);
  if (!mc_) return;
  auto w = pool_.acquire();
  const int per_point = n * (n + 1) / 2;
  for (int j = 0; j < n_points(); ++j)
    holonomic_hessian(x, lambda, j, *w, values.segment(static_cast<long>(N_) * stage_entries_ + j * per_point, per_point));
}

}  // namespace hovi
