#include "hovi/trajopt/lagrangian_hessian.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "hovi/errors.hpp"

namespace hovi {

LagrangianHessian::LagrangianHessian(const NlpProgram& program, HessianColouring colouring)
    : p_(program), c_(std::move(colouring)) {
  const int n = p_.n_variables();
  const long e = c_.rows.size();
  if (c_.colour.size() != n)
    throw InputError("colour must have one entry per variable (" + std::to_string(n) + "), got " +
                     std::to_string(c_.colour.size()));
  if (c_.cols.size() != e || c_.read_row.size() != e || c_.read_col.size() != e)
    throw InputError("rows, cols, read_row and read_col must have the same length");
  n_colours_ = n == 0 ? 0 : c_.colour.maxCoeff() + 1;
  if (n > 0 && c_.colour.minCoeff() < 0) throw InputError("colours must be non-negative");
  for (long k = 0; k < e; ++k) {
    const int idx[4] = {c_.rows[k], c_.cols[k], c_.read_row[k], c_.read_col[k]};
    for (int i : idx)
      if (i < 0 || i >= n) throw InputError("Hessian entry " + std::to_string(k) + " out of range");
    if (c_.rows[k] < c_.cols[k]) throw InputError("Hessian entries must be in the lower triangle (row >= col)");
  }
  by_colour_.assign(n_colours_, {});
  for (int j = 0; j < n; ++j) by_colour_[c_.colour[j]].push_back(j);
  entries_.assign(n_colours_, {});
  for (int k = 0; k < e; ++k) entries_[c_.colour[c_.read_col[k]]].push_back(k);
  // the quadratic costs' Hessian read at the entries (exact, sigma H)
  const SparseRowMatrix& H = p_.cost_hessian();
  cost_values_.resize(e);
  for (int k = 0; k < e; ++k) cost_values_[k] = H.coeff(c_.rows[k], c_.cols[k]);
}

void LagrangianHessian::values(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> values) const {
  const int n = p_.n_variables();
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  VecX g0(n), g(n), xh = x;
  p_.curved_gradient(x, lambda, sigma, g0);
  values = sigma * cost_values_;
  for (int c = 0; c < n_colours_; ++c) {
    for (int j : by_colour_[c]) xh[j] = x[j] + root_eps * std::max(1.0, std::abs(x[j]));
    p_.curved_gradient(xh, lambda, sigma, g);
    for (int k : entries_[c]) {
      const int j = c_.read_col[k];
      values[k] += (g[c_.read_row[k]] - g0[c_.read_row[k]]) / (xh[j] - x[j]);
    }
    for (int j : by_colour_[c]) xh[j] = x[j];
  }
}

}  // namespace hovi
