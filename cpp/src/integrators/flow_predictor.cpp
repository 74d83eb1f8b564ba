#include "hovi/integrators/flow_predictor.hpp"

#include <algorithm>

#include "hovi/algorithms/dynamics.hpp"
#include "hovi/errors.hpp"

namespace hovi {

FlowPredictor::FlowPredictor(const Model& model)
    : q_(model.n()), v_(model.n()), qs_(model.n()), vs_(model.n()), tau_(model.n()), u0_(model.n_controls()),
      um_(model.n_controls()), u1_(model.n_controls()) {
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

bool FlowPredictor::predict(const Model& model, const Quadrature& quad, double dt, Data& data,
                            const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc) {
  try {
    q_ = qc.col(0);
    v_ = mass_matrix_solve(model, data, q_, p);  // q̇^k = M(q^k)^{-1} p^k
    for (int a = 1; a <= quad.s; ++a) {
      const double h = (quad.c[a] - quad.c[a - 1]) * dt;
      if (u.rows() > 0) {  // the controls at the interval's start, middle and end (linear in between)
        u0_ = u.col(a - 1);
        u1_ = u.col(a);
        um_ = 0.5 * (u0_ + u1_);
      }
      kq_[0] = v_;
      acceleration(model, data, q_, v_, u0_, kv_[0]);
      for (int j = 1; j < 4; ++j) {
        const double f = j < 3 ? 0.5 * h : h;  // classical RK4: stages at h/2, h/2, h
        qs_ = q_ + f * kq_[j - 1];
        vs_ = v_ + f * kv_[j - 1];
        kq_[j] = vs_;
        acceleration(model, data, qs_, vs_, j < 3 ? um_ : u1_, kv_[j]);
      }
      q_ += (h / 6) * (kq_[0] + 2 * kq_[1] + 2 * kq_[2] + kq_[3]);
      v_ += (h / 6) * (kv_[0] + 2 * kv_[1] + 2 * kv_[2] + kv_[3]);
      if (!q_.allFinite() || !v_.allFinite()) return false;
      qc.col(a) = q_;
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
