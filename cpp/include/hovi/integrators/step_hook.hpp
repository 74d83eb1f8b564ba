// What a rollout asks before each step when the controls are not given in advance: a feedback
// policy, an MPC solve or a disturbance sets step k's controls from the state the step starts from
// and may change that state's momentum (an impulse). Rollouts call it in C++, so closed loops run
// without returning to Python.
#pragma once
#include "hovi/spatial/types.hpp"

namespace hovi {

class StepHook {
 public:
  virtual ~StepHook() = default;
  // Before step k from (q, p): set uk (m x (s+1), the controls at the step's control points) and
  // optionally add an impulse to p. False: the controller has no controls for this state (e.g. an
  // MPC solve failed from it), and the rollout ends there with status ControllerFailed. Exceptions
  // stop the rollout and reach its caller.
  virtual bool before_step(int k, const VecX& q, VecX& p, MatX& uk) = 0;
};

}  // namespace hovi
