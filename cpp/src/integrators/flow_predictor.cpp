#include "hovi/integrators/flow_predictor.hpp"

#include <algorithm>
#include <cmath>

#include "hovi/algorithms/dynamics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

FlowPredictor::FlowPredictor(const Model& model)
    : q_(model.n()), v_(model.n()), qs_(model.n()), vs_(model.n()), q0_(model.n()), v0_(model.n()), a0_(model.n()),
      a1_(model.n()), tau_(model.n()), u0_(model.n_controls()), um_(model.n_controls()), u1_(model.n_controls()) {
  const int n = model.n();
  for (int j = 0; j < 4; ++j) {
    kq_[j].resize(n);
    kv_[j].resize(n);
  }
}

void FlowPredictor::acceleration(const Model& model, Data& data, const VecX& q, const VecX& v, const VecX& u_t,
                                 VecX& dv) {
  const JointForces& jf = model.joint_forces;
  tau_.setZero();
  if (jf.has_springs()) tau_ += jf.preload - jf.stiffness.cwiseProduct(q);  // Q = -k (q - qref)
  if (jf.has_dampers()) tau_ -= jf.damping.cwiseProduct(v);               //     - c q̇
  if (jf.n_controls() > 0) tau_.noalias() += jf.actuation * u_t;           //     + B u
  dv = forward_dynamics(model, data, q, v, tau_);
}

int FlowPredictor::substeps(const Quadrature& quad) {
  double longest = 0;
  for (int a = 1; a <= quad.s; ++a) longest = std::max(longest, quad.c[a] - quad.c[a - 1]);
  return std::max(1, std::min(quad.s, static_cast<int>(std::lround(1 / longest))));
}

void FlowPredictor::control_at(const Quadrature& quad, const Eigen::Ref<const MatX>& u, double x, VecX& u_t) const {
  if (u.rows() == 0) return;
  int a = 1;
  while (a < quad.s && quad.c[a] < x) ++a;  // x in [c^{a-1}, c^a]
  const double w = (x - quad.c[a - 1]) / (quad.c[a] - quad.c[a - 1]);
  u_t = (1 - w) * u.col(a - 1) + w * u.col(a);
}

void FlowPredictor::rk4(const Model& model, Data& data, double h, const VecX& a0, const VecX& u_mid,
                        const VecX& u_end) {
  kq_[0] = v_;
  kv_[0] = a0;
  for (int j = 1; j < 4; ++j) {
    const double f = j < 3 ? 0.5 * h : h;  // classical RK4: stages at h/2, h/2, h
    qs_ = q_ + f * kq_[j - 1];
    vs_ = v_ + f * kv_[j - 1];
    kq_[j] = vs_;
    acceleration(model, data, qs_, vs_, j < 3 ? u_mid : u_end, kv_[j]);
  }
  q_ += (h / 6) * (kq_[0] + 2 * kq_[1] + 2 * kq_[2] + kq_[3]);
  v_ += (h / 6) * (kv_[0] + 2 * kv_[1] + 2 * kv_[2] + kv_[3]);
}

bool FlowPredictor::predict(const Model& model, const Quadrature& quad, double dt, Data& data,
                            const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc) {
  try {
    const int s = quad.s, m = substeps(quad);
    const bool at_nodes = m == s;  // one step per Lobatto interval: its ends are the control points
    q_ = qc.col(0);
    v_ = mass_matrix_solve(model, data, q_, p);  // q̇^k = M(q^k)^{-1} p^k
    control_at(quad, u, 0, u0_);
    acceleration(model, data, q_, v_, u0_, a0_);
    // Otherwise m < s equal steps, the control points read off the quintic Hermite interpolant of
    // (q, q̇, q̈) at the ends of each: 4 m + 1 forward-dynamics passes (4 s at the nodes).
    int a = 1;
    for (int j = 0; j < m; ++j) {
      const double x0 = at_nodes ? quad.c[j] : double(j) / m, x1 = at_nodes ? quad.c[j + 1] : double(j + 1) / m;
      const double h = (x1 - x0) * dt;
      q0_ = q_;
      v0_ = v_;
      control_at(quad, u, 0.5 * (x0 + x1), um_);  // the controls linear between the control points
      control_at(quad, u, x1, u1_);
      rk4(model, data, h, a0_, um_, u1_);
      if (!q_.allFinite() || !v_.allFinite()) return false;
      if (at_nodes) {
        qc.col(j + 1) = q_;
        if (j + 1 < m) acceleration(model, data, q_, v_, u1_, a0_);
        continue;
      }
      acceleration(model, data, q_, v_, u1_, a1_);
      if (!a1_.allFinite()) return false;
      for (; a <= s && (quad.c[a] * m <= j + 1 || j == m - 1); ++a) {
        const double x = quad.c[a] * m - j;  // in [0, 1] on this step
        const double x3 = x * x * x, x4 = x3 * x, x5 = x4 * x;
        qc.col(a) = (1 - 10 * x3 + 15 * x4 - 6 * x5) * q0_ + (10 * x3 - 15 * x4 + 6 * x5) * q_ +
                    (h * (x - 6 * x3 + 8 * x4 - 3 * x5)) * v0_ + (h * (-4 * x3 + 7 * x4 - 3 * x5)) * v_ +
                    (h * h * (0.5 * x * x - 1.5 * x3 + 1.5 * x4 - 0.5 * x5)) * a0_ +
                    (h * h * (0.5 * x3 - x4 + 0.5 * x5)) * a1_;
      }
      a0_.swap(a1_);
    }
    return true;
  } catch (const ModelError&) {  // a joint that moves no mass: the other predictors take over
    return false;
  }
}

bool PredictorChoice::flow() {
  if (mode_ == Predictor::Flow) return true;
  if (mode_ == Predictor::History) return false;
  return flowing_ && ++since_probe_ < probe_every_;  // false: a probe of the history is due
}

void PredictorChoice::observe(bool flow, int iterations) {
  if (mode_ != Predictor::Auto || flow) return;
  // The history's steps decide: more than enough_ iterations (kEnough, or kEnoughDense on the
  // dense path), take the flow, and probe the history again after twice as many steps as the last
  // time (16, 32, ... 1024: a failed probe costs as much as the flow saves on many steps); enough_
  // or fewer, keep the history.
  const bool probe_failed = flowing_ && iterations > enough_;
  probe_every_ = probe_failed ? std::min(2 * probe_every_, kProbeMax) : kProbeFirst;
  flowing_ = iterations > enough_;
  since_probe_ = 0;
}

}  // namespace hovi
