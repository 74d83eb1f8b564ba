#include "hovi/trajopt/nlp_program.hpp"

#include <chrono>
#include <string>

#include "hovi/errors.hpp"

namespace hovi {

namespace {
using Clock = std::chrono::steady_clock;
// Adds the nanoseconds since t0 to a timer.
void add_since(std::atomic<long long>& timer, Clock::time_point t0) {
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
    const auto t0 = Clock::now();
    VecX unused = VecX::Zero(n_);
    f += extra_.cost(x, unused);
    add_since(ns_extra_, t0);
  }
  return f;
}

void NlpProgram::gradient(const VecX& x, Eigen::Ref<VecX> grad) const {
  grad = S_.transpose() * d_.cwiseProduct(S_ * x - r_);
  if (extra_.cost) {
    const auto t0 = Clock::now();
    extra_.cost(x, grad);
    add_since(ns_extra_, t0);
  }
}

void NlpProgram::constraints(const VecX& x, Eigen::Ref<VecX> g) const {
  auto t0 = Clock::now();
  tr_.constraints(x, g.head(core_rows_));
  add_since(ns_core_, t0);
  if (extra_.rows > 0) {
    t0 = Clock::now();
    extra_.constraints(x, g.segment(core_rows_, extra_.rows));
    add_since(ns_extra_, t0);
  }
  g.tail(A_.rows()) = A_ * x;
}

void NlpProgram::jacobian(const VecX& x, Eigen::Ref<VecX> values) const {
  auto t0 = Clock::now();
  tr_.jacobian(x, values.head(core_nnz_));
  add_since(ns_core_, t0);
  if (extra_.rows > 0) {
    t0 = Clock::now();
    extra_.jacobian(x, values.segment(core_nnz_, extra_.nnz));
    add_since(ns_extra_, t0);
  }
  // A's values in its coordinate order (row-major, as python/hovi/trajopt/nlp.py lists them)
  values.tail(A_.nonZeros()) = Eigen::Map<const VecX>(A_.valuePtr(), A_.nonZeros());
}

void NlpProgram::curved_gradient(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> out, VecX& jac,
                                 Part part) const {
  jac.resize(nnz());
  out.setZero();
  const bool mine = part != Part::Extra, theirs = part != Part::Transcription;
  if (theirs && extra_.cost) {
    VecX g = VecX::Zero(n_);
    const auto t0 = Clock::now();
    extra_.cost(x, g);
    add_since(ns_extra_, t0);
    out = sigma * g;
  }
  if (mine) {
    const auto t0 = Clock::now();
    tr_.jacobian(x, jac.head(core_nnz_));
    add_since(ns_core_, t0);
    for (int k = 0; k < core_nnz_; ++k) out[jac_cols_[k]] += jac[k] * lambda[jac_rows_[k]];
  }
  if (theirs && extra_.rows > 0) {
    const auto t0 = Clock::now();
    extra_.jacobian(x, jac.segment(core_nnz_, extra_.nnz));
    add_since(ns_extra_, t0);
    for (int k = core_nnz_; k < core_nnz_ + extra_.nnz; ++k) out[jac_cols_[k]] += jac[k] * lambda[jac_rows_[k]];
  }
}

}  // namespace hovi
