#include "hovi/trajopt/complementarity_rows.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

ComplementarityRows::ComplementarityRows(const Model& model, int n_variables, ContactModel contacts, int first_input,
                                         VecX t, Eigen::VectorXi q_off, Eigen::VectorXi u_off)
    : model_(model), ct_(std::move(contacts)), nv_(n_variables), n_(model.n()), P_(static_cast<int>(t.size())),
      E_(P_ - 1), C_(ct_.size()), d_(ct_.d()), first_(first_input), hold_(ct_.unknowns()), q_off_(std::move(q_off)),
      u_off_(std::move(u_off)), pool_([this] { return std::make_unique<BodyPointWorkspace>(model_); }) {
  const auto fail = [](const std::string& why) { throw InputError("ComplementarityRows: " + why); };
  if (P_ < 2) fail("contact conditions need at least two configuration points");
  if (q_off_.size() != P_ || u_off_.size() != P_) fail("t, q_off and u_off must have one entry per point");
  if (!t.allFinite()) fail("the times t must be finite");
  if (!std::isfinite(ct_.mu) || !ct_.D.allFinite()) fail("mu and the friction directions must be finite");
  dt_ = t.tail(E_) - t.head(E_);
  if (!(dt_.minCoeff() > 0)) fail("the times t must increase");
  if (q_off_.minCoeff() < 0 || q_off_.maxCoeff() + n_ > nv_) fail("a configuration offset lies outside the variables");
  if (first_ < 0 || u_off_.minCoeff() < 0 || u_off_.maxCoeff() + first_ + hold_ > nv_)
    fail("a contact input lies outside the variables");
  ct_.terrain.check();
  for (const ContactPoint& c : ct_.points) {
    if (c.body < 0 || c.body >= n_) fail("body index " + std::to_string(c.body) + " out of range");
    if (!c.point.allFinite()) fail("a contact point must be finite");
    bodies_.push_back(c.body);
    path_.emplace_back();
    for (int j = c.body; j >= 0; j = model_.parent[j]) path_.back().push_back(j);
  }
  joints_ = model_.joints_moving(bodies_);
  r_com_ = ct_.points_in_com_frames(model_);
  std::vector<int> rows, cols;
  const auto entry = [&](int r, int s) {
    rows.push_back(std::max(r, s));
    cols.push_back(std::min(r, s));
  };
  for (int p = 0; p < P_; ++p)   // x's second derivatives at each point
    for (int a : joints_)
      for (int b : joints_)
        if (a >= b) entry(q_off_[p] + a, q_off_[p] + b);
  for (int e = 0; e < E_; ++e)   // the products' cross terms; hessian() fills them in this order
    for (int c = 0; c < C_; ++c) {
      for (int j : path_[c]) entry(input(e, c, 0), q_off_[e + 1] + j);
      entry(input(e, c, 1 + d_), input(e, c, 0));
      for (int k = 0; k < d_; ++k) entry(input(e, c, 1 + d_), input(e, c, 1 + k));
      for (int k = 0; k < d_; ++k) {
        for (int j : path_[c]) entry(input(e, c, 1 + k), q_off_[e + 1] + j);
        for (int j : path_[c]) entry(input(e, c, 1 + k), q_off_[e] + j);
        entry(input(e, c, 1 + k), input(e, c, 1 + d_));
      }
    }
  hs_.rows = Eigen::Map<Eigen::VectorXi>(rows.data(), static_cast<long>(rows.size()));
  hs_.cols = Eigen::Map<Eigen::VectorXi>(cols.data(), static_cast<long>(cols.size()));
}

int ComplementarityRows::nnz() const {
  const int per_pair = n_ + (1 + d_) + d_ * (2 * n_ + 1) + (n_ + 1) + (2 + d_) + d_ * (2 * n_ + 2);
  return E_ * C_ * per_pair + 2 * hold_;
}

void ComplementarityRows::points(const VecX& x, BodyPointWorkspace& w, bool jacobians) const {
  MatX Q(n_, P_);
  for (int p = 0; p < P_; ++p) Q.col(p) = x.segment(q_off_[p], n_);
  body_point_kinematics(model_, w.data, Q, bodies_, r_com_, w.X, jacobians ? &w.J : nullptr);
}

void ComplementarityRows::values(const VecX& x, Eigen::Ref<VecX> g) const {
  auto w = pool_.acquire();
  points(x, *w, false);
  const int EC = E_ * C_;
  for (int e = 0; e < E_; ++e)
    for (int c = 0; c < C_; ++c) {
      const int i = e * C_ + c;
      const Vec3 xa = w->X.col((e + 1) * C_ + c), v = (xa - w->X.col(e * C_ + c)) / dt_[e];
      const double phi = ct_.gap(c, xa);
      const double lam = x[input(e, c, 0)], gam = x[input(e, c, 1 + d_)];
      double psi = ct_.mu * lam;
      for (int k = 0; k < d_; ++k) psi -= x[input(e, c, 1 + k)];
      g[i] = phi;
      g[EC + i] = psi;
      g[(2 + d_) * EC + i] = lam * phi;
      g[(3 + d_) * EC + i] = gam * psi;
      for (int k = 0; k < d_; ++k) {
        const double zeta = gam + ct_.D.row(k).dot(v);
        g[(2 + k) * EC + i] = zeta;
        g[(4 + d_ + k) * EC + i] = x[input(e, c, 1 + k)] * zeta;
      }
    }
  const int rows0 = (4 + 2 * d_) * EC, last = u_off_[P_ - 1] + first_, before = u_off_[P_ - 2] + first_;
  for (int i = 0; i < hold_; ++i) g[rows0 + i] = x[last + i] - x[before + i];
}

void ComplementarityRows::jacobian(const VecX& x, Eigen::Ref<VecX> values) const {
  auto w = pool_.acquire();
  points(x, *w, true);
  int at = 0;
  const auto put = [&](const auto& block) {
    values.segment(at, block.size()) = block;
    at += static_cast<int>(block.size());
  };
  const auto one = [&](double v) { values[at++] = v; };
  const auto each_pair = [&](const auto& f) {
    for (int e = 0; e < E_; ++e)
      for (int c = 0; c < C_; ++c) f(e, c);
  };
  // the row kinds in the order of complementarity.py's _pieces
  each_pair([&](int e, int c) { put(jac(*w, e + 1, c).row(2).transpose()); });                          // phi
  each_pair([&](int, int) {                                                                              // psi
    one(ct_.mu);
    for (int k = 0; k < d_; ++k) one(-1.0);
  });
  for (int k = 0; k < d_; ++k)                                                                           // zeta_k
    each_pair([&](int e, int c) {
      put((jac(*w, e + 1, c).transpose() * ct_.D.row(k).transpose() / dt_[e]).eval());
      put((-jac(*w, e, c).transpose() * ct_.D.row(k).transpose() / dt_[e]).eval());
      one(1.0);
    });
  each_pair([&](int e, int c) {                                                                          // lambda phi
    const Vec3 xa = w->X.col((e + 1) * C_ + c);
    put((x[input(e, c, 0)] * jac(*w, e + 1, c).row(2).transpose()).eval());
    one(ct_.gap(c, xa));
  });
  each_pair([&](int e, int c) {                                                                          // gamma psi
    const double lam = x[input(e, c, 0)], gam = x[input(e, c, 1 + d_)];
    double psi = ct_.mu * lam;
    for (int k = 0; k < d_; ++k) psi -= x[input(e, c, 1 + k)];
    one(psi);
    one(gam * ct_.mu);
    for (int k = 0; k < d_; ++k) one(-gam);
  });
  for (int k = 0; k < d_; ++k)                                                                           // beta_k zeta_k
    each_pair([&](int e, int c) {
      const double beta = x[input(e, c, 1 + k)], gam = x[input(e, c, 1 + d_)];
      const Vec3 v = (w->X.col((e + 1) * C_ + c) - w->X.col(e * C_ + c)) / dt_[e];
      put((beta / dt_[e] * jac(*w, e + 1, c).transpose() * ct_.D.row(k).transpose()).eval());
      put((-beta / dt_[e] * jac(*w, e, c).transpose() * ct_.D.row(k).transpose()).eval());
      one(beta);
      one(gam + ct_.D.row(k).dot(v));
    });
  for (int i = 0; i < hold_; ++i) {                                                                      // hold
    one(1.0);
    one(-1.0);
  }
}

void ComplementarityRows::hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const {
  auto w = pool_.acquire();
  const int EC = E_ * C_;
  const auto mult = [&](int kind, int e, int c) { return lambda[kind * EC + e * C_ + c]; };
  // the world vector each contact point's position is weighted by, at each point
  MatX F = MatX::Zero(3, C_ * P_);
  for (int e = 0; e < E_; ++e)
    for (int c = 0; c < C_; ++c) {
      F.col((e + 1) * C_ + c).z() += mult(0, e, c) + mult(2 + d_, e, c) * x[input(e, c, 0)];   // phi, lambda phi
      for (int k = 0; k < d_; ++k) {   // zeta_k, beta_k zeta_k
        const Vec3 f = (mult(2 + k, e, c) + mult(4 + d_ + k, e, c) * x[input(e, c, 1 + k)]) / dt_[e] *
                       ct_.D.row(k).transpose();
        F.col((e + 1) * C_ + c) += f;
        F.col(e * C_ + c) -= f;
      }
    }
  int at = 0;
  MatX H(n_, n_);
  points(x, *w, true);   // the Jacobians, for the cross terms
  const KinematicsView kin{model_, w->data.g.data(), w->data.Sbar.data(), 1};
  for (int p = 0; p < P_; ++p) {
    forward_kinematics(model_, w->data, x.segment(q_off_[p], n_));   // the view d(J^T F)/dq reads
    H.setZero();
    for (int c = 0; c < C_; ++c) body_point_force_derivative(kin, bodies_[c], r_com_.col(c), F.col(p * C_ + c), H);
    for (int a : joints_)
      for (int b : joints_)
        if (a >= b) values[at++] = 0.5 * (H(a, b) + H(b, a));
  }
  for (int e = 0; e < E_; ++e)   // in the order of the constructor's entries
    for (int c = 0; c < C_; ++c) {
      const double mu_lp = mult(2 + d_, e, c), mu_gp = mult(3 + d_, e, c);
      const auto Ja = jac(*w, e + 1, c), Jb = jac(*w, e, c);
      for (int j : path_[c]) values[at++] = mu_lp * Ja(2, j);
      values[at++] = mu_gp * ct_.mu;
      for (int k = 0; k < d_; ++k) values[at++] = -mu_gp;
      for (int k = 0; k < d_; ++k) {
        const double mu_bz = mult(4 + d_ + k, e, c);
        for (int j : path_[c]) values[at++] = mu_bz / dt_[e] * ct_.D.row(k).dot(Ja.col(j));
        for (int j : path_[c]) values[at++] = -mu_bz / dt_[e] * ct_.D.row(k).dot(Jb.col(j));
        values[at++] = mu_bz;
      }
    }
}

}  // namespace hovi
