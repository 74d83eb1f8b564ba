// The nonlinear program of a transcribed problem, evaluated in C++ for a solver's callbacks
// (python/hovi/trajopt/nlp.py builds it and keeps its layout):
//   objective  f(x) = c + sum_i d_i (S x - r)_i^2 / 2 (the built-in costs are weighted squares of
//              samples, which are linear in x, less their references; written as residuals, not
//              expanded, so that no digits cancel) + the terms the caller evaluates (user costs),
//   rows       g(x) = [dynamics (the transcription) | the built-in rows and the caller's | A x],
//   Jacobian   values in the order [transcription's structure | built-in and caller's | A's],
//   Hessian    of sigma f + lambda^T g (lagrangian_hessian.hpp).
// The built-in rows (body-point path constraints, contact complementarity) are C++ RowBlocks with
// their own Hessians; the caller's parts (Python costs and path constraints) come through
// `ExtraTerms`. Both write their rows and Jacobian values at the places they are given in the middle
// segment, so that the NLP keeps its order of rows; a problem without Python terms never leaves C++.
#pragma once
#include <Eigen/SparseCore>
#include <atomic>
#include <functional>
#include <vector>

#include "hovi/trajopt/row_block.hpp"
#include "hovi/trajopt/transcription.hpp"

namespace hovi {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Parts of the program the caller evaluates; a function left empty is absent. Its rows land at
// `rows` of g and its Jacobian values at `entries` of the Jacobian's values.
struct ExtraTerms {
  Eigen::VectorXi rows, entries;
  std::function<double(const VecX& x, Eigen::Ref<VecX> grad)> cost;         // adds its gradient to grad
  std::function<void(const VecX& x, Eigen::Ref<VecX> g)> constraints;       // rows.size() values
  std::function<void(const VecX& x, Eigen::Ref<VecX> values)> jacobian;     // entries.size() values
};

class NlpProgram {
 public:
  // transcription: kept by reference (the caller keeps it alive). S (k, n), r (k,), d (k,) >= 0: the
  // squares; A (a, n): the linear rows; blocks and extra: the middle segment's rows and Jacobian
  // values, each place taken once; jac_rows/jac_cols: the whole Jacobian's structure.
  NlpProgram(const Transcription& transcription, double c, SparseRowMatrix S, VecX r, VecX d, SparseRowMatrix A,
             std::vector<PlacedRows> blocks, ExtraTerms extra, Eigen::VectorXi jac_rows, Eigen::VectorXi jac_cols);

  int n_variables() const { return n_; }
  int n_constraints() const { return m_; }
  int nnz() const { return static_cast<int>(jac_rows_.size()); }
  const Eigen::VectorXi& jac_rows() const { return jac_rows_; }
  const Eigen::VectorXi& jac_cols() const { return jac_cols_; }
  const SparseRowMatrix& cost_hessian() const { return H_; }   // S^T diag(d) S
  const Transcription& transcription() const { return tr_; }
  const std::vector<PlacedRows>& blocks() const { return blocks_; }
  bool has_python() const { return extra_.rows.size() > 0 || bool(extra_.cost); }

  double objective(const VecX& x) const;
  void gradient(const VecX& x, Eigen::Ref<VecX> grad) const;
  void constraints(const VecX& x, Eigen::Ref<VecX> g) const;
  void jacobian(const VecX& x, Eigen::Ref<VecX> values) const;
  // The parts of the Lagrangian a Hessian takes apart (flags, combined with |).
  enum Part { Dynamics = 1, BuiltIn = 2, Python = 4, All = 7 };   // the transcription, the row blocks, the caller's terms
  // The gradient of the parts' non-quadratic Lagrangian, sigma grad f_python + J(x)^T lambda over
  // their rows (the linear rows' part is constant): what the Hessian differences. The C++ parts may
  // run concurrently. `jac` holds the Jacobian's values (resized to nnz()): one per thread.
  void curved_gradient(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> out, VecX& jac,
                       int parts = All) const;
  // The transcription's own Hessian of lambda^T g (lambda: all the rows), timed with its evaluations.
  void transcription_hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values, int threads) const;
  // Block b's own Hessian of lambda^T g over its rows, timed with the C++ evaluations.
  void block_hessian(int b, const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const;
  // Seconds spent in the C++ evaluations (transcription and built-in rows) and in the caller's
  // (Python) since the last reset.
  double cpp_seconds() const { return 1e-9 * static_cast<double>(ns_cpp_.load()); }
  double python_seconds() const { return 1e-9 * static_cast<double>(ns_python_.load()); }
  void reset_timers() const { ns_cpp_ = 0; ns_python_ = 0; }

 private:
  const Transcription& tr_;
  double c_;
  SparseRowMatrix S_;
  VecX r_, d_;
  SparseRowMatrix H_, A_;
  std::vector<PlacedRows> blocks_;
  ExtraTerms extra_;
  Eigen::VectorXi jac_rows_, jac_cols_;
  int n_, m_, core_rows_, core_nnz_;
  mutable std::atomic<long long> ns_cpp_{0}, ns_python_{0};
};

}  // namespace hovi
