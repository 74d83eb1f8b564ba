#include "hovi/control/box_fddp.hpp"

#include <chrono>
#include <cmath>
#include <limits>

#include "hovi/control/box_qp.hpp"
#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"

namespace hovi {

BoxFddp::BoxFddp(const ShootingProblem& problem, FddpOptions options)
    : pb_(problem), opt_(options), N_(problem.N()), nx_(problem.nx()), nu_(problem.nu()) {
  if (opt_.max_iterations < 0 || !(opt_.tol > 0) || !(opt_.reg_min > 0) || !(opt_.reg_max >= opt_.reg_min))
    throw InputError("FDDP options: max_iterations >= 0, tol > 0 and 0 < reg_min <= reg_max");
}

void BoxFddp::start(const MatX& xs_init, const MatX& us_init) {
  const int N = N_;
  if (us_init.size() && (us_init.rows() != N || us_init.cols() != nu_ || !us_init.allFinite()))
    throw InputError("the initial controls must be finite, (N, m) = (" + std::to_string(N) + ", " + std::to_string(nu_) + ")");
  if (xs_init.size() && (xs_init.rows() != N + 1 || xs_init.cols() != nx_ || !xs_init.allFinite()))
    throw InputError("the initial states must be finite, (N+1, 2n) = (" + std::to_string(N + 1) + ", " +
                     std::to_string(nx_) + ")");
  xs_.assign(N + 1, VecX());
  us_.assign(N, VecX());
  fs_.assign(N + 1, VecX::Zero(nx_));
  xnext_.assign(N, VecX());
  qc_.assign(N, MatX());
  zs_.assign(N, VecX());
  d_.assign(N, StageDerivatives());
  Vx_.assign(N + 1, VecX::Zero(nx_));
  Vxx_.assign(N + 1, MatX::Zero(nx_, nx_));
  Qu_.assign(N, VecX::Zero(nu_));
  k_.assign(N, VecX::Zero(nu_));
  K_.assign(N, MatX::Zero(nu_, nx_));
  Quu_.assign(N, MatX::Zero(nu_, nu_));
  for (int k = 0; k < N; ++k)
    us_[k] = (us_init.size() ? VecX(us_init.row(k).transpose()) : VecX::Zero(nu_)).cwiseMax(pb_.u_lower()).cwiseMin(pb_.u_upper());
  cost_ = 0;
  xs_[0] = xs_init.size() ? VecX(xs_init.row(0).transpose()) : pb_.x0();
  for (int k = 0; k < N; ++k) {
    if (!pb_.step(xs_[k], us_[k], xnext_[k], qc_[k], false, zs_[k]))
      throw InputError("FDDP: the step from the initial guess failed at step " + std::to_string(k) +
                       " (give another initial guess or a smaller dt)");
    cost_ += pb_.stage_cost(k, qc_[k], us_[k]);
    xs_[k + 1] = xs_init.size() ? VecX(xs_init.row(k + 1).transpose()) : xnext_[k];
  }
  if (pb_.extra) cost_ += pb_.extra->value(qc_, us_);
  fs_[0] = pb_.x0() - xs_[0];
  double gap = fs_[0].cwiseAbs().maxCoeff();
  for (int k = 0; k < N; ++k) {
    fs_[k + 1] = xnext_[k] - xs_[k + 1];
    gap = std::max(gap, fs_[k + 1].cwiseAbs().maxCoeff());
  }
  feasible_ = gap == 0;
  reg_ = opt_.reg_init;
}

bool BoxFddp::calc_derivatives() {
  std::vector<char> ok(N_, 1);
  std::vector<VecX> eg;
  std::vector<MatX> eH;
  if (pb_.extra) pb_.extra->derivatives(qc_, us_, eg, eH);
  const auto errors = parallel_for(N_, std::max(1, opt_.threads), [&](int k, int) {
    ok[k] = pb_.extra ? pb_.derivatives(k, qc_[k], us_[k], zs_[k], d_[k], &eg[k], &eH[k])
                      : pb_.derivatives(k, qc_[k], us_[k], zs_[k], d_[k]);
  });
  for (int k = 0; k < N_; ++k)
    if (!ok[k] || !errors[k].empty()) return false;
  return true;
}

bool BoxFddp::backward_pass() {
  Vx_[N_].setZero();
  Vxx_[N_].setZero();
  stop_ = dg_ = dq_ = 0;
  MatX Qxx, Qux, Quu, AtV;
  VecX Qx, Qu;
  for (int k = N_ - 1; k >= 0; --k) {
    const StageDerivatives& d = d_[k];
    const VecX& Vxp = Vx_[k + 1];
    const MatX& Vxxp = Vxx_[k + 1];
    Qx = d.lx + d.A.transpose() * Vxp;
    Qu = d.lu + d.B.transpose() * Vxp;
    AtV = d.A.transpose() * Vxxp;
    Qxx = d.lxx + AtV * d.A;
    const MatX BtV = d.B.transpose() * Vxxp;
    Qux = d.lux + BtV * d.A;
    Quu = d.luu + BtV * d.B;
    Quu.diagonal().array() += reg_;
    const BoxQpResult qp = box_qp(Quu, Qu, pb_.u_lower() - us_[k], pb_.u_upper() - us_[k], k_[k]);
    if (!qp.ok) return false;
    k_[k] = qp.x;
    K_[k].setZero();
    std::vector<int> fr;
    for (int i = 0; i < nu_; ++i)
      if (qp.free[i]) fr.push_back(i);
    if (!fr.empty()) {
      MatX Qf(fr.size(), nx_);
      for (std::size_t i = 0; i < fr.size(); ++i) Qf.row(i) = Qux.row(fr[i]);
      const MatX Kf = -qp.llt.solve(Qf);
      for (std::size_t i = 0; i < fr.size(); ++i) K_[k].row(fr[i]) = Kf.row(i);
    }
    for (int i = 0; i < nu_; ++i) {  // the projected gradient: a control held at its bound by Q_u is stationary
      const bool at_lo = us_[k][i] <= pb_.u_lower()[i] && Qu[i] > 0, at_hi = us_[k][i] >= pb_.u_upper()[i] && Qu[i] < 0;
      Qu_[k][i] = (at_lo || at_hi) ? 0.0 : Qu[i];
    }
    stop_ += Qu_[k].squaredNorm();
    const VecX Quuk = Quu * k_[k];
    dg_ -= Qu.dot(k_[k]);
    dq_ -= k_[k].dot(Quuk);
    Vx_[k] = Qx + K_[k].transpose() * (Quuk + Qu) + Qux.transpose() * k_[k];
    MatX V = Qxx + K_[k].transpose() * Quu * K_[k] + K_[k].transpose() * Qux + Qux.transpose() * K_[k];
    Vxx_[k] = 0.5 * (V + V.transpose());
    Vxx_[k].diagonal().array() += reg_;
    if (!feasible_) Vx_[k] += Vxx_[k] * fs_[k];
    Quu_[k] = Quu;
    if (!Vx_[k].allFinite() || !Vxx_[k].allFinite()) return false;
  }
  if (!feasible_)
    for (int k = 0; k <= N_; ++k) {
      dg_ -= Vx_[k].dot(fs_[k]);
      dq_ += fs_[k].dot(Vxx_[k] * fs_[k]);
    }
  return true;
}

bool BoxFddp::compute_direction() {
  if (!calc_derivatives()) return false;
  while (!backward_pass()) {
    if (reg_ >= opt_.reg_max) return false;
    reg_ = std::min(reg_ * 10, opt_.reg_max);
  }
  return true;
}

double BoxFddp::expected_improvement(double alpha) const { return alpha * (dg_ + 0.5 * alpha * dq_); }

double BoxFddp::try_step(double alpha) {
  xs_try_.assign(N_ + 1, VecX());
  us_try_.assign(N_, VecX());
  xnext_try_.assign(N_, VecX());
  qc_try_.assign(N_, MatX());
  zs_try_ = zs_;  // each step's impulses start from its last
  xs_try_[0] = xs_[0] + alpha * fs_[0];
  double cost = 0;
  for (int k = 0; k < N_; ++k) {
    us_try_[k] = (us_[k] + alpha * k_[k] + K_[k] * (xs_try_[k] - xs_[k])).cwiseMax(pb_.u_lower()).cwiseMin(pb_.u_upper());
    qc_try_[k] = qc_[k];  // the guess: this stage's last control points, moved with q^k
    qc_try_[k].rightCols(pb_.s()).colwise() += xs_try_[k].head(nx_ / 2) - xs_[k].head(nx_ / 2);
    if (!pb_.step(xs_try_[k], us_try_[k], xnext_try_[k], qc_try_[k], true, zs_try_[k]))
      return std::numeric_limits<double>::infinity();
    cost += pb_.stage_cost(k, qc_try_[k], us_try_[k]);
    xs_try_[k + 1] = xnext_try_[k] - (1 - alpha) * fs_[k + 1];
    if (!std::isfinite(cost)) return cost;
  }
  if (pb_.extra) cost += pb_.extra->value(qc_try_, us_try_);
  return cost;
}

void BoxFddp::accept_trial(double alpha) {
  xs_.swap(xs_try_);
  us_.swap(us_try_);
  xnext_.swap(xnext_try_);
  qc_.swap(qc_try_);
  zs_.swap(zs_try_);
  cost_ = cost_try_;
  fs_[0] = pb_.x0() - xs_[0];
  for (int k = 0; k < N_; ++k) fs_[k + 1] = xnext_[k] - xs_[k + 1];
  if (alpha == 1) {
    for (auto& f : fs_) f.setZero();  // the rollout closed every gap
    feasible_ = true;
  }
}

// Feasible, and the projected gradient below tol or the expected decrease at round-off (the floor
// of stop is about 1e-13 on the swing-ups: a tighter tol would spin there).
bool BoxFddp::stopping_criteria() const {
  return feasible_ && (stop_ < opt_.tol || std::abs(dg_) <= 1e-15 * (1 + std::abs(cost_)));
}

FddpResult BoxFddp::solve(const MatX& xs_init, const MatX& us_init) {
  const auto t0 = std::chrono::steady_clock::now();
  start(xs_init, us_init);
  FddpResult out;
  out.status = "max_iterations";
  static const double alphas[] = {1, 0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625, 0.0078125, 0.00390625, 0.001953125};
  int it = 0;
  for (; it < opt_.max_iterations; ++it) {
    if (!compute_direction()) {
      out.status = "regularisation_limit";
      break;
    }
    if (stopping_criteria()) {
      out.status = "converged";
      out.converged = true;
      break;
    }
    double taken = 0;
    for (double alpha : alphas) {
      cost_try_ = try_step(alpha);
      if (!std::isfinite(cost_try_)) continue;
      const double dV = cost_ - cost_try_, expected = expected_improvement(alpha);
      const bool accept = expected >= 0 ? dV > opt_.accept * expected : dV > opt_.accept_negative * expected;
      if (accept || dg_ < 1e-14) {
        accept_trial(alpha);
        taken = alpha;
        break;
      }
    }
    double gap = 0;
    for (const auto& f : fs_) gap = std::max(gap, f.cwiseAbs().maxCoeff());
    out.trace.push_back({cost_, stop_, taken, reg_, gap});
    if (taken == 0) {  // no step: more regularisation
      if (reg_ >= opt_.reg_max) {
        out.status = "regularisation_limit";
        ++it;
        break;
      }
      reg_ = std::min(reg_ * 10, opt_.reg_max);
    } else if (taken > 0.5) {
      reg_ = std::max(reg_ / 10, opt_.reg_min);
    } else if (taken <= 0.01) {
      reg_ = std::min(reg_ * 10, opt_.reg_max);
    }
  }
  out.iterations = it;
  out.xs.resize(N_ + 1, nx_);
  out.us.resize(N_, nu_);
  out.control_points.resize(N_, (pb_.s() + 1) * nx_ / 2);
  for (int k = 0; k <= N_; ++k) out.xs.row(k) = xs_[k].transpose();
  for (int k = 0; k < N_; ++k) {
    out.us.row(k) = us_[k].transpose();
    out.control_points.row(k) = Eigen::Map<const VecX>(qc_[k].data(), qc_[k].size()).transpose();
  }
  out.impulses.resize(N_, pb_.impulses());
  for (int k = 0; k < N_ && pb_.impulses(); ++k) out.impulses.row(k) = zs_[k].transpose();
  out.K = K_;
  out.cost = cost_;
  out.stop = stop_;
  out.feasible = feasible_;
  for (const auto& f : fs_) out.gaps = std::max(out.gaps, f.cwiseAbs().maxCoeff());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace hovi
