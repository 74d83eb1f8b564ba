#include "hovi/control/mpc.hpp"

#include "hovi/errors.hpp"

namespace hovi {

MpcHook::MpcHook(ShootingProblem& problem, FddpOptions options, int period, const Model& plant,
                 const std::vector<Push>& pushes, const MatX& us_init)
    : pb_(problem), opt_(options), period_(period), pushes_(plant, pushes), us_init_(us_init) {
  if (period < 1 || period > problem.N()) throw InputError("the MPC period must be between 1 and the horizon N steps");
  if (plant.n() != problem.nx() / 2 || plant.n_controls() != problem.nu())
    throw InputError("the plant's n and m must be the controller's");
}

bool MpcHook::before_step(int k, const VecX& q, VecX& p, MatX& uk) {
  pushes_.apply(k, q, p);
  const int n = pb_.nx() / 2, N = pb_.N();
  VecX x(2 * n);
  x << q, p;
  if (k == 0 || since_ >= period_) {
    MatX xs, us = us_init_;
    if (k > 0) {  // the last plan shifted by `period` steps, the end held
      xs.resize(N + 1, 2 * n);
      us.resize(N, pb_.nu());
      for (int j = 0; j <= N; ++j) xs.row(j) = plan_.xs.row(std::min(j + since_, N));
      for (int j = 0; j < N; ++j) us.row(j) = plan_.us.row(std::min(j + since_, N - 1));
      xs.row(0) = x.transpose();
    }
    pb_.offset = k;
    pb_.set_x0(x);
    BoxFddp solver(pb_, opt_);
    try {
      try {
        plan_ = solver.solve(xs, us);
      } catch (const InputError&) {  // a step from the shifted plan failed: start from the rollout of its controls
        if (!xs.size()) throw;
        plan_ = solver.solve(MatX(), us);
      }
    } catch (const InputError& e) {  // no plan from this state (its rollout fails): the run ends here
      failure_ = e.what();
      return false;
    }
    stats_.solve_seconds.push_back(plan_.seconds);
    stats_.iterations.push_back(plan_.iterations);
    stats_.converged.push_back(plan_.converged ? 1 : 0);
    since_ = 0;
  }
  const int j = since_;
  const VecX u = (plan_.us.row(j).transpose() + plan_.K[j] * (x - plan_.xs.row(j).transpose()))
                     .cwiseMax(pb_.u_lower())
                     .cwiseMin(pb_.u_upper());
  uk = u.replicate(1, uk.cols());
  ++since_;
  return true;
}

}  // namespace hovi
