// A feedback policy on the integrator's state x = (q, p) and the pushes of a closed-loop run.
// At step k:  u^{k,a} = clamp(u_ref^{k,a} - K^k (x^k - x_ref^k), lower, upper),  a = 0..s
// (the feedback held over the step, the feed-forward at each control point): LQR at an equilibrium
// (one reference and gain) or time-varying LQR along a trajectory (one per step; past its last
// step, the last). A model with a free base: x^k - x_ref^k is in tangent coordinates,
// (q ⊖ q_ref, p - p_ref) = (FreeBase::difference(q_ref, q), p - p_ref), its states public (q: nq, p: n).
#pragma once
#include <optional>
#include <vector>

#include "hovi/algorithms/free_base.hpp"
#include "hovi/integrators/step_hook.hpp"
#include "hovi/model/data.hpp"

namespace hovi {

struct Policy {
  MatX x_ref;           // S x (nq + n): x_ref^k = (q, p)
  MatX u_ref;           // S x ((s+1) m), row k = vec(u^{k,0..s}) column-major, as rollout's u
  std::vector<MatX> K;  // S gains, m x 2n
  VecX lower, upper;    // m: saturation (±inf: none)

  int stages() const { return int(K.size()); }
  // Throws InputError unless the sizes fit the model's nq, n and m and s, and every entry is finite
  // (limits: lower <= upper).
  void check(const Model& model, int s) const;
  // uk (m x (s+1)) at step k from the state (q, p); base: the model's free base, if it has one.
  void control(int k, const Eigen::Ref<const VecX>& q, const Eigen::Ref<const VecX>& p, MatX& uk,
               const FreeBase* base = nullptr) const;
};

// A push: the world impulse `impulse` (N s) at `point` (in the joint frame of `body`) and the world
// angular impulse `angular` (N m s) on the body, applied at knot `step`: a wrench impulse,
// p^k += J_x(q^k)^T impulse + J_ω(q^k)^T angular (J_x the point's, J_ω the body's angular Jacobian;
// a free base: in the chart about q^k's attitude, then mapped to the public momentum).
struct Push {
  int step;
  int body;
  Vec3 point;
  Vec3 impulse;
  Vec3 angular = Vec3::Zero();
};

// The pushes of a run, applied at their knots (PolicyHook, MpcHook).
class PushSchedule {
 public:
  // model and pushes must outlive it.
  PushSchedule(const Model& model, const std::vector<Push>& pushes);
  // p += J(q)^T impulse for every push at step k.
  void apply(int k, const VecX& q, VecX& p);

 private:
  const Model& model_;
  const std::vector<Push>& pushes_;
  std::optional<FreeBase> base_;
  Data data_;
  MatX J_;
};

// The StepHook of a closed loop: the pushes of step k, then the policy's controls.
class PolicyHook : public StepHook {
 public:
  // model, policy and pushes must outlive it.
  PolicyHook(const Model& model, const Policy& policy, const std::vector<Push>& pushes)
      : policy_(policy), pushes_(model, pushes) {
    if (model.rotation_chart >= 0) base_.emplace(model);
  }
  bool before_step(int k, const VecX& q, VecX& p, MatX& uk) override {
    pushes_.apply(k, q, p);
    policy_.control(k, q, p, uk, base_ ? &*base_ : nullptr);
    return true;
  }

 private:
  const Policy& policy_;
  PushSchedule pushes_;
  std::optional<FreeBase> base_;
};

// Throws InputError naming the push unless its body exists and its numbers are finite.
void check_pushes(const Model& model, const std::vector<Push>& pushes);

}  // namespace hovi
