#include "hovi/integrators/lcp.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace hovi {

namespace {
// Relative: what z < 0 or w < 0 may be and still count as zero; looser for the bases of a regularised
// problem, ill-conditioned (1e9 and more) by the redundant contacts that called for it (the caller
// checks the complements of the nonlinear step).
constexpr double kRoundOff = 1e-11, kRegularisedRoundOff = 1e-9;
}

bool LcpSolver::solve_basis(const MatX& M, const VecX& b, const std::vector<char>& basis, VecX& z, double tol) {
  const int n = static_cast<int>(b.size());
  rows_.clear();
  for (int i = 0; i < n; ++i)
    if (basis[i]) rows_.push_back(i);
  const int k = static_cast<int>(rows_.size());
  z.setZero(n);
  if (k) {
    Mbb_.resize(k, k);
    rhs_.resize(k);
    for (int i = 0; i < k; ++i) {
      rhs_[i] = -b[rows_[i]];
      for (int j = 0; j < k; ++j) Mbb_(i, j) = M(rows_[i], rows_[j]);
    }
    const Eigen::FullPivLU<MatX> lu(Mbb_);
    if (!lu.isInvertible()) return false;
    const VecX zb = lu.solve(rhs_);
    if (!zb.allFinite() || !(Mbb_ * zb - rhs_).isZero(1e-9 * (1 + rhs_.cwiseAbs().maxCoeff()))) return false;
    for (int i = 0; i < k; ++i) z[rows_[i]] = zb[i];
  }
  w_.noalias() = M * z;
  w_ += b;
  const double zs = tol * (1 + z.cwiseAbs().maxCoeff()), ws = tol * (1 + b.cwiseAbs().maxCoeff());
  for (int i = 0; i < n; ++i) {
    if (z[i] < -zs || (!basis[i] && w_[i] < -ws)) return false;
    z[i] = std::max(z[i], 0.0);
  }
  return true;
}

bool LcpSolver::lemke(const MatX& M, const VecX& b, std::vector<char>& basis) {
  const int n = static_cast<int>(b.size()), z0 = 2 * n, rhs = 2 * n + 1;
  // Tableau of I w - M z - e z0 = b; var_[row]: the basic variable of the row (w_i = i, z_i = n + i, z0 = 2n).
  T_.setZero(n, 2 * n + 2);
  T_.leftCols(n).setIdentity();
  T_.middleCols(n, n) = -M;
  T_.col(z0).setConstant(-1);
  T_.col(rhs) = b;
  var_.resize(n);
  for (int i = 0; i < n; ++i) var_[i] = i;
  auto pivot = [&](int r, int c) {
    T_.row(r) /= T_(r, c);
    for (int i = 0; i < n; ++i)
      if (i != r && T_(i, c) != 0) T_.row(i) -= T_(i, c) * T_.row(r);
    var_[r] = c;
    ++pivots_;
  };
  int r;
  b.minCoeff(&r);
  pivot(r, z0);
  int entering = n + r;  // the complement of the leaving w_r
  const int max_pivots = 50 * (n + 1);
  while (pivots_ < max_pivots) {
    const double scale = T_.col(entering).cwiseAbs().maxCoeff();
    int row = -1;
    double best = INFINITY, best_piv = 0;
    for (int i = 0; i < n; ++i) {
      const double a = T_(i, entering);
      if (!(a > 1e-12 * scale)) continue;
      const double ratio = T_(i, rhs) / a;
      const double tie = 1e-12 * (1 + std::abs(best));
      // the least ratio; among ties z0 leaves (termination), else the largest pivot (stability)
      const bool take = row < 0 || ratio < best - tie ||
                        (ratio <= best + tie && var_[row] != z0 && (var_[i] == z0 || a > best_piv));
      if (take) {
        best = row < 0 ? ratio : std::min(best, ratio);
        row = i;
        best_piv = a;
      }
    }
    if (row < 0) return false;  // a secondary ray
    const int leaving = var_[row];
    pivot(row, entering);
    if (leaving == z0) {
      std::fill(basis.begin(), basis.end(), 0);
      for (int i = 0; i < n; ++i)
        if (var_[i] >= n && var_[i] < z0) basis[var_[i] - n] = 1;
      return true;
    }
    entering = leaving < n ? leaving + n : leaving - n;
  }
  return false;
}

bool LcpSolver::solve(const MatX& M, const VecX& b, VecX& z, std::vector<char>& basis) {
  const int n = static_cast<int>(b.size());
  pivots_ = 0;
  basis.resize(n, 0);
  z.setZero(n);
  if (n == 0 || b.minCoeff() >= 0) {  // z = 0 solves it
    std::fill(basis.begin(), basis.end(), 0);
    return b.allFinite();
  }
  if (std::any_of(basis.begin(), basis.end(), [](char c) { return c != 0; }) && solve_basis(M, b, basis, z, kRoundOff))
    return true;
  if (lemke(M, b, basis) && solve_basis(M, b, basis, z, kRoundOff)) return true;
  // Redundant contacts (the corners of two flat feet: M of rank 28 in 48) can end Lemke on a ray of
  // a feasible LCP, or on a basis too near singular to re-solve; M + eps I is solved instead (eps
  // relative to M's largest diagonal entry, itself of the order dt / mass: the complements move by
  // eps z, far below the caller's tolerance, which checks them), its basis re-solved on M if M allows.
  for (const double eps : {1e-9, 1e-6}) {
    pivots_ = 0;
    Mreg_ = M;
    Mreg_.diagonal().array() += eps * (M.diagonal().cwiseAbs().maxCoeff() + 1e-300);
    if (lemke(Mreg_, b, basis) &&
        (solve_basis(M, b, basis, z, kRoundOff) || solve_basis(Mreg_, b, basis, z, kRegularisedRoundOff)))
      return true;
  }
  return false;
}

}  // namespace hovi
