#include "hovi/trajopt/nlp_program.hpp"

#include <chrono>
#include <string>
#include <vector>

#include "hovi/errors.hpp"

namespace hovi {

namespace {
using Clock = std::chrono::steady_clock;
// f(), its nanoseconds added to a timer.
template <class F>
void timed(std::atomic<long long>& timer, F&& f) {
  const auto t0 = Clock::now();
  f();
  timer += std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
}
// out[at[i]] = values[i].
void place(const VecX& values, const Eigen::VectorXi& at, Eigen::Ref<VecX> out) {
  for (int i = 0; i < at.size(); ++i) out[at[i]] = values[i];
}
}  // namespace

NlpProgram::NlpProgram(const Transcription& transcription, double c, SparseRowMatrix S, VecX r, VecX d,
                       SparseRowMatrix A, std::vector<PlacedRows> blocks, ExtraTerms extra, Eigen::VectorXi jac_rows,
                       Eigen::VectorXi jac_cols)
    : tr_(transcription), c_(c), S_(std::move(S)), r_(std::move(r)), d_(std::move(d)), A_(std::move(A)),
      blocks_(std::move(blocks)), extra_(std::move(extra)), jac_rows_(std::move(jac_rows)),
      jac_cols_(std::move(jac_cols)) {
  n_ = tr_.n_variables();
  core_rows_ = tr_.n_constraints();
  core_nnz_ = tr_.structure().nnz();
  const auto size = [](const std::string& what, long got, long want) {
    if (got != want) throw InputError(what + " has " + std::to_string(got) + " entries, expected " + std::to_string(want));
  };
  // the middle segment: every row and Jacobian value placed once
  long mid_rows = extra_.rows.size(), mid_nnz = extra_.entries.size();
  for (const PlacedRows& b : blocks_) {
    if (!b.block) throw InputError("a row block is missing");
    size("a row block's variables", b.block->n_variables(), n_);
    size("a row block's row places", b.rows.size(), b.block->rows());
    size("a row block's Jacobian places", b.entries.size(), b.block->nnz());
    mid_rows += b.rows.size();
    mid_nnz += b.entries.size();
  }
  const auto placed_once = [](const std::string& what, long count, long first, const auto& places) {
    std::vector<int> taken(count, 0);
    for (const Eigen::VectorXi* at : places)
      for (int i = 0; i < at->size(); ++i) {
        const long k = (*at)[i] - first;
        if (k < 0 || k >= count || taken[k]++)
          throw InputError(what + " place " + std::to_string((*at)[i]) + " is out of range or taken twice");
      }
  };
  std::vector<const Eigen::VectorXi*> row_places{&extra_.rows}, value_places{&extra_.entries};
  for (const PlacedRows& b : blocks_) {
    row_places.push_back(&b.rows);
    value_places.push_back(&b.entries);
  }
  placed_once("a row", mid_rows, core_rows_, row_places);
  placed_once("a Jacobian value", mid_nnz, core_nnz_, value_places);
  m_ = core_rows_ + static_cast<int>(mid_rows) + static_cast<int>(A_.rows());
  size("the squares' columns", S_.cols(), n_);
  size("r", r_.size(), S_.rows());
  size("d", d_.size(), S_.rows());
  if (d_.size() > 0 && !(d_.minCoeff() >= 0.0)) throw InputError("the squares' weights d must be >= 0");
  size("the linear rows' columns", A_.cols(), n_);
  size("jac_rows", jac_rows_.size(), core_nnz_ + mid_nnz + A_.nonZeros());
  size("jac_cols", jac_cols_.size(), jac_rows_.size());
  if (extra_.rows.size() > 0 && !(extra_.constraints && extra_.jacobian))
    throw InputError("extra constraint rows need both a constraints and a jacobian function");
  for (int k = 0; k < jac_rows_.size(); ++k)
    if (jac_rows_[k] < 0 || jac_rows_[k] >= m_ || jac_cols_[k] < 0 || jac_cols_[k] >= n_)
      throw InputError("Jacobian entry " + std::to_string(k) + " out of range");
  A_.makeCompressed();
  H_ = SparseRowMatrix(S_.transpose() * d_.asDiagonal() * S_);
}

double NlpProgram::objective(const VecX& x) const {
  const VecX e = S_ * x - r_;
  double f = c_ + 0.5 * e.dot(d_.cwiseProduct(e));
  if (extra_.cost) {
    VecX unused = VecX::Zero(n_);
    timed(ns_python_, [&] { f += extra_.cost(x, unused); });
  }
  return f;
}

void NlpProgram::gradient(const VecX& x, Eigen::Ref<VecX> grad) const {
  grad = S_.transpose() * d_.cwiseProduct(S_ * x - r_);
  if (extra_.cost) timed(ns_python_, [&] { extra_.cost(x, grad); });
}

void NlpProgram::constraints(const VecX& x, Eigen::Ref<VecX> g) const {
  timed(ns_cpp_, [&] {
    tr_.constraints(x, g.head(core_rows_));
    for (const PlacedRows& b : blocks_) {
      VecX scratch(b.rows.size());
      b.block->values(x, scratch);
      place(scratch, b.rows, g);
    }
  });
  if (extra_.rows.size() > 0)
    timed(ns_python_, [&] {
      VecX scratch(extra_.rows.size());
      extra_.constraints(x, scratch);
      place(scratch, extra_.rows, g);
    });
  g.tail(A_.rows()) = A_ * x;
}

void NlpProgram::jacobian(const VecX& x, Eigen::Ref<VecX> values) const {
  timed(ns_cpp_, [&] {
    tr_.jacobian(x, values.head(core_nnz_));
    for (const PlacedRows& b : blocks_) {
      VecX scratch(b.entries.size());
      b.block->jacobian(x, scratch);
      place(scratch, b.entries, values);
    }
  });
  if (extra_.rows.size() > 0)
    timed(ns_python_, [&] {
      VecX scratch(extra_.entries.size());
      extra_.jacobian(x, scratch);
      place(scratch, extra_.entries, values);
    });
  // A's values in its coordinate order (row-major, as python/hovi/trajopt/nlp.py lists them)
  values.tail(A_.nonZeros()) = Eigen::Map<const VecX>(A_.valuePtr(), A_.nonZeros());
}

void NlpProgram::transcription_hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values, int threads) const {
  timed(ns_cpp_, [&] { tr_.hessian(x, lambda.head(core_rows_), values, threads); });
}

void NlpProgram::block_hessian(int b, const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const {
  const PlacedRows& block = blocks_.at(b);
  timed(ns_cpp_, [&] {
    VecX mine(block.rows.size());
    for (int i = 0; i < mine.size(); ++i) mine[i] = lambda[block.rows[i]];
    block.block->hessian(x, mine, values);
  });
}

void NlpProgram::curved_gradient(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> out, VecX& jac,
                                 int parts) const {
  jac.resize(nnz());
  out.setZero();
  if ((parts & Python) && extra_.cost) {
    VecX g = VecX::Zero(n_);
    timed(ns_python_, [&] { extra_.cost(x, g); });
    out = sigma * g;
  }
  // J^T lambda over the Jacobian's values at `at`, computed into `values`
  const auto add_jt_lambda = [&](const VecX& values, const Eigen::VectorXi& at) {
    for (int i = 0; i < at.size(); ++i) out[jac_cols_[at[i]]] += values[i] * lambda[jac_rows_[at[i]]];
  };
  if (parts & Dynamics) {
    timed(ns_cpp_, [&] { tr_.jacobian(x, jac.head(core_nnz_)); });
    for (int k = 0; k < core_nnz_; ++k) out[jac_cols_[k]] += jac[k] * lambda[jac_rows_[k]];
  }
  if (parts & BuiltIn)
    for (const PlacedRows& b : blocks_) {
      VecX values(b.entries.size());
      timed(ns_cpp_, [&] { b.block->jacobian(x, values); });
      add_jt_lambda(values, b.entries);
    }
  if ((parts & Python) && extra_.rows.size() > 0) {
    VecX values(extra_.entries.size());
    timed(ns_python_, [&] { extra_.jacobian(x, values); });
    add_jt_lambda(values, extra_.entries);
  }
}

}  // namespace hovi
