// The nonlinear program of a transcribed problem, evaluated in C++ for a solver's callbacks
// (python/hovi/trajopt/nlp.py builds it and keeps its layout):
//   objective  f(x) = c + sum_i d_i (S x - r)_i^2 / 2 (the built-in costs are weighted squares of
//              samples, which are linear in x, less their references; written as residuals, not
//              expanded, so that no digits cancel) + the terms the caller evaluates (user costs),
//   rows       g(x) = [dynamics (the transcription) | the caller's rows | A x],
//   Jacobian   values in the order [transcription's structure | caller's | A's],
//   Hessian    of sigma f + lambda^T g (lagrangian_hessian.hpp).
// The caller's parts (Python costs, path constraints, contact rows) come through `ExtraTerms`; a
// problem without them never leaves C++.
#pragma once
#include <Eigen/SparseCore>
#include <atomic>
#include <functional>

#include "hovi/trajopt/transcription.hpp"

namespace hovi {

using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// Parts of the program the caller evaluates; a function left empty is absent.
struct ExtraTerms {
  int rows = 0, nnz = 0;                                                    // its constraint rows and Jacobian nonzeros
  std::function<double(const VecX& x, Eigen::Ref<VecX> grad)> cost;         // adds its gradient to grad
  std::function<void(const VecX& x, Eigen::Ref<VecX> g)> constraints;       // rows values
  std::function<void(const VecX& x, Eigen::Ref<VecX> values)> jacobian;     // nnz values
};

class NlpProgram {
 public:
  // transcription: kept by reference (the caller keeps it alive). S (k, n), r (k,), d (k,) >= 0: the
  // squares; A (a, n): the linear rows; jac_rows/jac_cols: the whole Jacobian's structure, nnz =
  // the transcription's + extra + A's.
  NlpProgram(const Transcription& transcription, double c, SparseRowMatrix S, VecX r, VecX d, SparseRowMatrix A,
             ExtraTerms extra, Eigen::VectorXi jac_rows, Eigen::VectorXi jac_cols);

  int n_variables() const { return n_; }
  int n_constraints() const { return m_; }
  int nnz() const { return static_cast<int>(jac_rows_.size()); }
  const Eigen::VectorXi& jac_rows() const { return jac_rows_; }
  const Eigen::VectorXi& jac_cols() const { return jac_cols_; }
  const SparseRowMatrix& cost_hessian() const { return H_; }   // S^T diag(d) S
  const Transcription& transcription() const { return tr_; }
  bool has_extra() const { return extra_.rows > 0 || bool(extra_.cost); }

  double objective(const VecX& x) const;
  void gradient(const VecX& x, Eigen::Ref<VecX> grad) const;
  void constraints(const VecX& x, Eigen::Ref<VecX> g) const;
  void jacobian(const VecX& x, Eigen::Ref<VecX> values) const;
  // The gradient of the non-quadratic part of the Lagrangian, sigma grad f_extra + J(x)^T lambda
  // without the linear rows (whose part is constant): what the Hessian differences; or only its
  // transcription's part (C++, may run concurrently) or only the caller's part. `jac` holds the
  // Jacobian's values (resized to nnz()): one per thread.
  enum class Part { All, Transcription, Extra };
  void curved_gradient(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> out, VecX& jac,
                       Part part = Part::All) const;
  // The transcription's own Hessian of lambda^T g (Transcription::hessian; lambda: all the rows),
  // timed with its evaluations.
  void transcription_hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values, int threads) const;
  // Seconds spent in the transcription's and in the caller's evaluations since the last reset.
  double transcription_seconds() const { return 1e-9 * static_cast<double>(ns_core_.load()); }
  double extra_seconds() const { return 1e-9 * static_cast<double>(ns_extra_.load()); }
  void reset_timers() const { ns_core_ = 0; ns_extra_ = 0; }

 private:
  const Transcription& tr_;
  double c_;
  SparseRowMatrix S_;
  VecX r_, d_;
  SparseRowMatrix H_, A_;
  ExtraTerms extra_;
  Eigen::VectorXi jac_rows_, jac_cols_;
  int n_, m_, core_rows_, core_nnz_;
  mutable std::atomic<long long> ns_core_{0}, ns_extra_{0};
};

}  // namespace hovi
