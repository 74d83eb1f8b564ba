#include "hovi/trajopt/variational_transcription.hpp"

#include <cmath>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/errors.hpp"
#include "hovi/trajopt/jacobian_blocks.hpp"

namespace hovi {


VariationalTranscription::Workspace::Workspace(const Model& aug, const Model& model, const Quadrature& quad)
    : del(aug, quad), jac(aug, quad), data(model) {}

VariationalTranscription::VariationalTranscription(const Model& model, int s, int N, double dt, ControlMode controls)
    : aug_(model.n_constraints() ? with_constraint_forces(model) : model), model_(model), quad_(s), N_(N),
      n_(model.n()), m_(model.n_controls()), mc_(model.n_constraints()), dt_(dt), controls_(controls),
      pool_([this] { return std::make_unique<Workspace>(aug_, model_, quad_); }) {
  if (n_ == 0) throw ModelError("the model has no joints");
  if (N < 1) throw InputError("the number of stages N must be at least 1, got " + std::to_string(N));
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite, got " + std::to_string(dt));
  n_variables_ = lambda_offset() + N_ * s * mc_;
  n_rows_ = holonomic_row() + n_points() * mc_;
  build_structure();
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

}  // namespace hovi
