#include "hovi/trajopt/nlp_program.hpp"

#include <chrono>
#include <string>

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
}  // namespace

NlpProgram::NlpProgram(const Transcription& transcription, double c, SparseRowMatrix S, VecX r, VecX d,
                       SparseRowMatrix A, ExtraTerms extra, Eigen::VectorXi jac_rows, Eigen::VectorXi jac_cols)
    : tr_(transcription), c_(c), S_(std::move(S)), r_(std::move(r)), d_(std::move(d)), A_(std::move(A)),
      extra_(std::move(extra)), jac_rows_(std::move(jac_rows)), jac_cols_(std::move(jac_cols)) {
  n_ = tr_.n_variables();
  core_rows_ = tr_.n_constraints();
  core_nnz_ = tr_.structure().nnz();
  m_ = core_rows_ + extra_.rows + static_cast<int>(A_.rows());
  const auto size = [](const std::string& what, long got, long want) {
    if (got != want) throw InputError(what + " has " + std::to_string(got) + " entries, expected " + std::to_string(want));
  };
  size("the squares' columns", S_.cols(), n_);
  size("r", r_.size(), S_.rows());
  size("d", d_.size(), S_.rows());
  if (d_.size() > 0 && !(d_.minCoeff() >= 0.0)) throw InputError("the squares' weights d must be >= 0");
  size("the linear rows' columns", A_.cols(), n_);
  size("jac_rows", jac_rows_.size(), core_nnz_ + extra_.nnz + A_.nonZeros());
  size("jac_cols", jac_cols_.size(), jac_rows_.size());
  if (extra_.rows > 0 && !(extra_.constraints && extra_.jacobian))
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
    timed(ns_extra_, [&] { f += extra_.cost(x, unused); });
  }
  return f;
}

void NlpProgram::gradient(const VecX& x, Eigen::Ref<VecX> grad) const {
  grad = S_.transpose() * d_.cwiseProduct(S_ * x - r_);
  if (extra_.cost) timed(ns_extra_, [&] { extra_.cost(x, grad); });
}

void NlpProgram::constraints(const VecX& x, Eigen::Ref<VecX> g) const {
  timed(ns_core_, [&] { tr_.constraints(x, g.head(core_rows_)); });
  if (extra_.rows > 0) timed(ns_extra_, [&] { extra_.constraints(x, g.segment(core_rows_, extra_.rows)); });
  g.tail(A_.rows()) = A_ * x;
}

void NlpProgram::jacobian(const VecX& x, Eigen::Ref<VecX> values) const {
  timed(ns_core_, [&] { tr_.jacobian(x, values.head(core_nnz_)); });
  if (extra_.rows > 0) timed(ns_extra_, [&] { extra_.jacobian(x, values.segment(core_nnz_, extra_.nnz)); });
  // A's values in its coordinate order (row-major, as python/hovi/trajopt/nlp.py lists them)
  values.tail(A_.nonZeros()) = Eigen::Map<const VecX>(A_.valuePtr(), A_.nonZeros());
}

void NlpProgram::transcription_hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values, int threads) const {
  timed(ns_core_, [&] { tr_.hessian(x, lambda.head(core_rows_), values, threads); });
}

void NlpProgram::curved_gradient(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> out, VecX& jac,
                                 Part part) const {
  jac.resize(nnz());
  out.setZero();
  const bool mine = part != Part::Extra, theirs = part != Part::Transcription;
  if (theirs && extra_.cost) {
    VecX g = VecX::Zero(n_);
    timed(ns_extra_, [&] { extra_.cost(x, g); });
    out = sigma * g;
  }
  // J^T lambda over the Jacobian's entries [begin, end)
  const auto add_jt_lambda = [&](int begin, int end) {
    for (int k = begin; k < end; ++k) out[jac_cols_[k]] += jac[k] * lambda[jac_rows_[k]];
  };
  if (mine) {
    timed(ns_core_, [&] { tr_.jacobian(x, jac.head(core_nnz_)); });
    add_jt_lambda(0, core_nnz_);
  }
  if (theirs && extra_.rows > 0) {
    timed(ns_extra_, [&] { extra_.jacobian(x, jac.segment(core_nnz_, extra_.nnz)); });
    add_jt_lambda(core_nnz_, core_nnz_ + extra_.nnz);
  }
}

}  // namespace hovi
