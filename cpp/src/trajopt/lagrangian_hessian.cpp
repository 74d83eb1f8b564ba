#include "hovi/trajopt/lagrangian_hessian.hpp"

#include <cmath>
#include <algorithm>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>
#include <string>
#include <unordered_map>

#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

namespace hovi {

std::pair<Eigen::VectorXi, Eigen::VectorXi> probed_pattern(const NlpProgram& program, const Pattern& P,
                                                           const VecX& x0, unsigned seed, bool own_structures) {
  using Part = NlpProgram::Part;
  const int nv = program.n_variables();
  if (P.size() != nv || x0.size() != nv) throw InputError("the pattern and x must have one entry per variable");
  const bool own_dynamics = own_structures && program.transcription().has_hessian();
  const int probed = own_structures ? (own_dynamics ? 0 : Part::Dynamics) | (program.has_python() ? Part::Python : 0)
                                    : Part::All;
  std::vector<std::vector<int>> entries(nv);          // entries[i]: columns k of row i found so far
  for (int j = 0; j < nv; ++j) entries[j].push_back(j);
  const SparseRowMatrix& H = program.cost_hessian();
  for (int i = 0; i < nv; ++i)
    for (SparseRowMatrix::InnerIterator it(H, i); it; ++it) entries[i].push_back(it.col());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  const VecX scale = 0.1 * x0.cwiseAbs().cwiseMax(1.0);
  VecX x(nv), lambda(program.n_constraints()), g0(nv), g(nv), jac, values;
  for (int j = 0; j < nv; ++j) x[j] = x0[j] + scale[j] * normal(rng);
  for (int i = 0; i < lambda.size(); ++i) lambda[i] = normal(rng);
  // the own Hessian's entries above its round-off at (x, lambda): its differences leave entries that
  // are zero at about 1e-18 of the largest, which the gradient differences did not see either
  const auto add_nonzero = [&](const SparsityStructure& T) {
    const double floor = values.size() == 0 ? 0.0 : 1e-14 * values.cwiseAbs().maxCoeff();
    for (int k = 0; k < T.nnz(); ++k)
      if (std::abs(values[k]) > floor) {
        entries[T.rows[k]].push_back(T.cols[k]);
        entries[T.cols[k]].push_back(T.rows[k]);
      }
  };
  if (own_dynamics) {
    values.resize(program.transcription().hessian_structure().nnz());
    program.transcription_hessian(x, lambda, values, 1);
    add_nonzero(program.transcription().hessian_structure());
  }
  for (int b = 0; own_structures && b < static_cast<int>(program.blocks().size()); ++b) {
    const SparsityStructure& T = program.blocks()[b].block->hessian_structure();
    values.resize(T.nnz());
    program.block_hessian(b, x, lambda, values);
    add_nonzero(T);
  }
  if (probed != 0) {
    const Eigen::VectorXi colour = distance2_colouring(P);
    const int n_colours = nv == 0 ? 0 : colour.maxCoeff() + 1;
    program.curved_gradient(x, lambda, 1.0, g0, jac, probed);
    std::vector<std::vector<int>> members(n_colours);
    for (int j = 0; j < nv; ++j) members[colour[j]].push_back(j);
    VecX xc = x;
    for (int c = 0; c < n_colours; ++c) {
      for (int j : members[c]) xc[j] = x[j] + scale[j] * normal(rng);
      program.curved_gradient(xc, lambda, 1.0, g, jac, probed);
      for (int i = 0; i < nv; ++i) {
        if (!(std::abs(g[i] - g0[i]) > 1e-12 * (1.0 + std::abs(g0[i])))) continue;
        for (int a = P.indptr[i]; a < P.indptr[i + 1]; ++a)   // at most one of colour c (distance-2 colours)
          if (colour[P.indices[a]] == c) {
            entries[i].push_back(P.indices[a]);
            entries[P.indices[a]].push_back(i);
          }
      }
      for (int j : members[c]) xc[j] = x[j];
    }
  }
  Eigen::VectorXi indptr(nv + 1);
  std::vector<int> indices;
  indptr[0] = 0;
  for (int i = 0; i < nv; ++i) {
    auto& e = entries[i];
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    indices.insert(indices.end(), e.begin(), e.end());
    indptr[i + 1] = static_cast<int>(indices.size());
  }
  return {indptr, Eigen::Map<Eigen::VectorXi>(indices.data(), static_cast<long>(indices.size()))};
}

LagrangianHessian::LagrangianHessian(const NlpProgram& program, HessianColouring colouring, int threads,
                                     bool by_differences)
    : p_(program), c_(std::move(colouring)), threads_(thread_count(threads)), by_differences_(by_differences),
      own_(!by_differences && program.transcription().has_hessian()) {
  using Part = NlpProgram::Part;
  differenced_ = by_differences ? Part::Dynamics | Part::BuiltIn : (own_ ? 0 : Part::Dynamics);
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
  // where the transcription's and the blocks' own entries land: entries outside the (probed)
  // pattern are zero there
  std::unordered_map<long long, int> entry;
  entry.reserve(e);
  for (int k = 0; k < e; ++k) entry[static_cast<long long>(c_.rows[k]) * n + c_.cols[k]] = k;
  const auto entries_of = [&](const SparsityStructure& T) {
    std::vector<int> at(T.nnz());
    for (int i = 0; i < T.nnz(); ++i) {
      const auto it = entry.find(static_cast<long long>(T.rows[i]) * n + T.cols[i]);
      at[i] = it == entry.end() ? -1 : it->second;
    }
    return at;
  };
  if (own_) own_entry_ = entries_of(p_.transcription().hessian_structure());
  if (!by_differences_)
    for (const PlacedRows& b : p_.blocks()) block_entry_.push_back(entries_of(b.block->hessian_structure()));
}

void LagrangianHessian::values(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> values) const {
  using Part = NlpProgram::Part;
  const int n = p_.n_variables();
  const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
  const int threads = std::max(1, std::min(threads_, n_colours_));
  std::vector<VecX> xh(threads, x), g(threads, VecX(n)), jac(threads);
  VecX g0 = VecX::Zero(n), read = VecX::Zero(nnz());   // read[k]: the gradient component entry k reads, at its colour's point
  const int python = p_.has_python() ? Part::Python : 0;
  const bool differences = (differenced_ | python) != 0;
  if (differences) p_.curved_gradient(x, lambda, sigma, g0, jac[0], differenced_ | python);
  // one colour's part of the gradient at its point; each colour adds only to its own entries, in
  // the same order on any number of threads (the C++ parts, then the caller's)
  const auto colour = [&](int c, int t, int parts) {
    for (int j : by_colour_[c]) xh[t][j] = x[j] + root_eps * std::max(1.0, std::abs(x[j]));
    p_.curved_gradient(xh[t], lambda, sigma, g[t], jac[t], parts);
    for (int k : entries_[c]) read[k] += g[t][c_.read_row[k]];
    for (int j : by_colour_[c]) xh[t][j] = x[j];
  };
  if (differenced_ && threads == 1) {
    for (int c = 0; c < n_colours_; ++c) colour(c, 0, differenced_);
  } else if (differenced_) {
    const std::vector<std::string> errors =
        parallel_for(n_colours_, threads, [&](int c, int t) { colour(c, t, differenced_); });
    for (const std::string& e : errors)
      if (!e.empty()) throw std::runtime_error("the Hessian's differences failed: " + e);
  }
  if (python)   // the caller's part (Python) on this thread
    for (int c = 0; c < n_colours_; ++c) colour(c, 0, Part::Python);
  values = sigma * cost_values_;
  if (differences)
    for (int k = 0; k < nnz(); ++k) {
      const int j = c_.read_col[k];
      const double step = (x[j] + root_eps * std::max(1.0, std::abs(x[j]))) - x[j];
      values[k] += (read[k] - g0[c_.read_row[k]]) / step;
    }
  const auto add = [&](const VecX& own, const std::vector<int>& at) {
    for (int i = 0; i < own.size(); ++i)
      if (at[i] >= 0) values[at[i]] += own[i];
  };
  if (own_) {
    VecX own(p_.transcription().hessian_structure().nnz());
    p_.transcription_hessian(x, lambda, own, threads_);
    add(own, own_entry_);
  }
  for (std::size_t b = 0; b < block_entry_.size(); ++b) {
    VecX own(block_entry_[b].size());
    p_.block_hessian(static_cast<int>(b), x, lambda, own);
    add(own, block_entry_[b]);
  }
}

}  // namespace hovi
