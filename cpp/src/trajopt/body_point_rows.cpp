#include "hovi/trajopt/body_point_rows.hpp"

#include <algorithm>
#include <string>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/kinematics.hpp"

namespace hovi {

namespace {
void check_size(const std::string& what, long got, long want) {
  if (got != want)
    throw InputError("BodyPointRows: " + what + " has " + std::to_string(got) + " entries where " +
                     std::to_string(want) + " were expected");
}
void check_finite(const std::string& what, const MatX& a) {
  if (!a.allFinite()) throw InputError("BodyPointRows: " + what + " must be finite");
}
}  // namespace

BodyPointRows::BodyPointRows(const Model& model, int n_variables, IndexMatrix offsets, MatX weights,
                             std::vector<int> bodies, MatX local, VecX c, MatX L, MatX D, IndexMatrix idx)
    : model_(model), nv_(n_variables), n_(model.n()), P_(static_cast<int>(offsets.rows())),
      K_(static_cast<int>(offsets.cols())), B_(static_cast<int>(bodies.size())), R_(static_cast<int>(c.size())),
      M_(static_cast<int>(idx.cols())), offsets_(std::move(offsets)), idx_(std::move(idx)), weights_(std::move(weights)),
      local_(std::move(local)), L_(std::move(L)), D_(std::move(D)), c_(std::move(c)), bodies_(std::move(bodies)),
      pool_([this] { return std::make_unique<BodyPointWorkspace>(model_); }) {
  check_size("weights' rows", weights_.rows(), P_);
  check_size("weights' columns", weights_.cols(), K_);
  check_size("local's rows", local_.rows(), B_);
  check_size("local's columns", local_.cols(), 3);
  check_size("idx's rows", idx_.rows(), R_);
  check_size("L's rows", L_.rows(), static_cast<long>(R_) * M_);
  check_size("D's rows", D_.rows(), static_cast<long>(R_) * M_);
  check_size("L's columns", L_.cols(), 3);
  check_size("D's columns", D_.cols(), 3);
  check_finite("weights", weights_);
  check_finite("local", local_);
  check_finite("c", c_);
  check_finite("L", L_);
  check_finite("D", D_);
  if (P_ > 0 && K_ > 0 && (offsets_.minCoeff() < 0 || offsets_.maxCoeff() + n_ > nv_))
    throw InputError("BodyPointRows: a configuration's offset lies outside the variables");
  if (R_ > 0 && M_ > 0 && (idx_.minCoeff() < 0 || idx_.maxCoeff() >= B_))
    throw InputError("BodyPointRows: idx names a point out of range");
  for (int b : bodies_)
    if (b < 0 || b >= n_) throw InputError("BodyPointRows: body index " + std::to_string(b) + " out of range");
  local_.transposeInPlace();
  for (int b = 0; b < B_; ++b) local_.col(b) = model_.point_in_com_frame(bodies_[b], local_.col(b));
  joints_ = model_.joints_moving(bodies_);
  squares_ = D_.size() > 0 && D_.cwiseAbs().maxCoeff() > 0;
  std::vector<int> rows, cols;
  for (int p = 0; p < P_; ++p)
    for (int k = 0; k < K_; ++k)
      for (int l = 0; l < K_; ++l)
        for (int a : joints_)
          for (int b : joints_) {
            const int r = offsets_(p, k) + a, s = offsets_(p, l) + b;
            if (r < s) continue;
            rows.push_back(r);
            cols.push_back(s);
          }
  hs_.rows = Eigen::Map<Eigen::VectorXi>(rows.data(), static_cast<long>(rows.size()));
  hs_.cols = Eigen::Map<Eigen::VectorXi>(cols.data(), static_cast<long>(cols.size()));
}

MatX BodyPointRows::configurations(const VecX& x) const {
  MatX Q = MatX::Zero(n_, P_);
  for (int p = 0; p < P_; ++p)
    for (int k = 0; k < K_; ++k) Q.col(p) += weights_(p, k) * x.segment(offsets_(p, k), n_);
  return Q;
}

Vec3 BodyPointRows::slope(int i, int m, const Vec3& xb) const {
  const int row = i * M_ + m;
  return L_.row(row).transpose() + 2.0 * D_.row(row).transpose().cwiseProduct(xb);
}

void BodyPointRows::values(const VecX& x, Eigen::Ref<VecX> g) const {
  auto w = pool_.acquire();
  body_point_kinematics(model_, w->data, configurations(x), bodies_, local_, w->X, nullptr);
  for (int p = 0; p < P_; ++p)
    for (int i = 0; i < R_; ++i) {
      double v = c_[i];
      for (int m = 0; m < M_; ++m) {
        const Vec3 xb = point(i, m, p, w->X);
        v += L_.row(i * M_ + m).dot(xb) + D_.row(i * M_ + m).dot(xb.cwiseProduct(xb));
      }
      g[p * R_ + i] = v;
    }
}

void BodyPointRows::jacobian(const VecX& x, Eigen::Ref<VecX> values) const {
  auto w = pool_.acquire();
  body_point_kinematics(model_, w->data, configurations(x), bodies_, local_, w->X, &w->J);
  VecX gi(n_);
  for (int p = 0; p < P_; ++p)
    for (int i = 0; i < R_; ++i) {
      gi.setZero();
      for (int m = 0; m < M_; ++m)
        gi += w->J.middleCols((p * B_ + idx_(i, m)) * n_, n_).transpose() * slope(i, m, point(i, m, p, w->X));
      for (int k = 0; k < K_; ++k) values.segment(((p * R_ + i) * K_ + k) * n_, n_) = weights_(p, k) * gi;
    }
}

void BodyPointRows::hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const {
  auto w = pool_.acquire();
  const MatX Q = configurations(x);
  body_point_kinematics(model_, w->data, Q, bodies_, local_, w->X, &w->J);
  const KinematicsView kin{model_, w->data.g.data(), w->data.Sbar.data(), 1};
  MatX H(n_, n_), F(3, B_);
  int e = 0;
  for (int p = 0; p < P_; ++p) {
    forward_kinematics(model_, w->data, Q.col(p));   // the view d(J^T F)/dq reads
    F.setZero();
    H.setZero();
    for (int i = 0; i < R_; ++i)
      for (int m = 0; m < M_; ++m) {
        const double li = lambda[p * R_ + i];
        F.col(idx_(i, m)) += li * slope(i, m, point(i, m, p, w->X));
        if (squares_) {   // 2 lambda J^T diag(D) J
          const auto J = w->J.middleCols((p * B_ + idx_(i, m)) * n_, n_);
          H.noalias() += 2.0 * li * J.transpose() * D_.row(i * M_ + m).transpose().asDiagonal() * J;
        }
      }
    for (int b = 0; b < B_; ++b) body_point_force_derivative(kin, bodies_[b], local_.col(b), F.col(b), H);
    for (int k = 0; k < K_; ++k)
      for (int l = 0; l < K_; ++l) {
        const double wkl = weights_(p, k) * weights_(p, l);
        for (int a : joints_)
          for (int b : joints_) {
            if (offsets_(p, k) + a < offsets_(p, l) + b) continue;
            values[e++] = 0.5 * wkl * (H(a, b) + H(b, a));
          }
      }
  }
}

}  // namespace hovi
