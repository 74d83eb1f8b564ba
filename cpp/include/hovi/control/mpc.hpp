// Model-predictive control: BoxFddp re-solved on a receding horizon inside the plant's step loop.
// Every `period` plant steps the shooting problem starts from the plant's state (x0), its cost
// references move on with time (offset = the step), and FDDP is warm-started from the previous
// solution shifted by `period` steps (its first rollout closes the gap to the new state with the
// previous feedback gains); at most max_iterations FDDP iterations per solve. Between solves the
// plan's feedback policy u^j = us^j + K^j (x - xs^j) runs. The plant's step must equal the
// problem's dt; it may be another model (mismatch) and have contacts.
#pragma once
#include <string>
#include <vector>

#include "hovi/control/box_fddp.hpp"
#include "hovi/control/policy.hpp"

namespace hovi {

struct MpcStats {
  std::vector<double> solve_seconds;  // per solve
  std::vector<int> iterations;        // FDDP iterations per solve
  std::vector<int> converged;         // 1 if that solve met its stopping criteria
};

class MpcHook : public StepHook {
 public:
  // problem and pushes must outlive it; us_init (N x m): the first solve's warm start (empty: zeros).
  MpcHook(ShootingProblem& problem, FddpOptions options, int period, const Model& plant,
          const std::vector<Push>& pushes, const MatX& us_init);
  // False when the solve from the plant's state fails (FDDP's rollout from it): failure() says why.
  bool before_step(int k, const VecX& q, VecX& p, MatX& uk) override;
  const MpcStats& stats() const { return stats_; }
  const std::string& failure() const { return failure_; }

 private:
  ShootingProblem& pb_;
  FddpOptions opt_;
  int period_;
  PushSchedule pushes_;
  FddpResult plan_;
  MatX us_init_;
  int since_ = 0;  // plant steps since the last solve
  MpcStats stats_;
  std::string failure_;
};

}  // namespace hovi
