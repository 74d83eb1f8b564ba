// The one Newton iteration of hovi, x_{k+1} = x_k + λ_k dx_k with dx_k = -J^{-1} r(x_k), shared by
// the integrator's NewtonSolver, the ConstrainedSolver, step_continuation's corrector and the
// baselines (Hermite-Simpson, the quasi-Newton of Lee et al.). In the shape of Crocoddyl's solver
// loop (computeDirection / tryStep / stoppingCriteria): newton_iterate() owns the control flow,
// the counters and the stopping rule; a Problem supplies the residual, the direction and the
// acceptance of a trial step. It is a template so that the hooks inline (no per-step dispatch, no
// allocation of its own).
//
// A Problem P has, at the current iterate x (its residual already evaluated on entry):
//   double residual_norm()          ||r(x)||_inf as reported (SolveInfo::residual)
//   double stationarity()           the norm the residual test reads (tol (1 + ||p||) scale)
//   bool finite()                   r(x) and what it outputs are finite
//   bool feasible()                 constraints met: the convergence tests apply (true if none)
//   double iterate_norm()           ||x||_inf, the scale of the correction test
//   bool has_factor()               a factorisation is kept from an earlier iterate
//   Factor factor()                 factors J(x) (or prepares the fixed J̃)
//   void direction()                dx = -J^{-1} r(x) with the kept factorisation
//   bool direction_finite(), double correction_norm()   on dx (||dx||_inf)
//   bool accept_direction(double dx, double previous)   the caller's own test on dx (continuation)
//   void trial(double lambda)       evaluates r at x + λ dx
//   bool sufficient_decrease(double lambda)   the line search's test of that trial
//   void commit()                   x <- x + λ dx (with its residual)
//   int restore()                   after a failed line search; residual evaluations it made
#pragma once
#include <algorithm>
#include <cmath>

namespace hovi {

// ContinuationStalled: step_continuation (step_continuation.hpp) found no solution at dt on the
// branch continuously connected to q^k (the branch turns back in the step length before dt).
// LcpFailed: the contact step's linear complementarity subproblem found no solution, or its solution
// missed the complementarity tolerance at the converged step.
enum class SolveStatus { Converged, MaxIterations, LineSearchFailed, SingularJacobian, NonFinite, ContinuationStalled,
                         LcpFailed, ControllerFailed };
const char* to_string(SolveStatus status);

struct SolveInfo {
  SolveStatus status = SolveStatus::MaxIterations;
  int iterations = 0;        // Newton directions computed
  int factorizations = 0;    // of them, those that refactored the Jacobian (the rest reused one)
  int residual_evaluations = 0;
  double residual = 0;       // ||r||_inf at exit
  bool converged() const { return status == SolveStatus::Converged; }
  // A later solve of the same step (a fallback, a stage): its counters added, its status and residual kept.
  void add(const SolveInfo& later) {
    status = later.status;
    iterations += later.iterations;
    factorizations += later.factorizations;
    residual_evaluations += later.residual_evaluations;
    residual = later.residual;
  }
};

// The stopping rule of every Newton iteration, on the next correction dx of an iterate x (the
// estimated error of x) and its residual r:
//   converged when ||r||_inf <= tol (1 + ||p||_inf) (tol > 0 only), or ||dx||_inf <= step_tol (1 + ||x||_inf),
//   or, after a full step dx_k, θ/(1-θ) ||dx_k|| <= step_tol (1 + ||x||) with θ = ||dx_k|| / ||dx_{k-1}|| < 1/2,
//   or at the round-off floor of r: below kFloor (1 + ||x||) the corrections of a fresh Jacobian stop
//   shrinking (more than half the smallest earlier one), or no fraction of one reduces the residual.
// The default step_tol: the correction at round-off (SolverOptions::step_tol says why).
constexpr double kStepTol = 1e-15;

class StoppingRule {
 public:
  static constexpr double kFloor = 1e-10;  // relative size of a correction that may be round-off
  StoppingRule(double tol, double step_tol, double residual_scale)
      : tol_(tol), step_tol_(step_tol), target_(tol * residual_scale) {}
  bool residual_small(double residual) const { return tol_ > 0 && residual <= target_; }
  bool correction_small(double dx, double smallest, double x_norm, bool fresh) const {
    const double scale = 1 + x_norm;
    return dx <= step_tol_ * scale || (fresh && dx > 0.5 * smallest && dx <= kFloor * scale);
  }
  bool contraction_small(double theta, double dx, double x_norm) const {
    return theta < 0.5 && theta / (1 - theta) * dx <= step_tol_ * (1 + x_norm);
  }
  bool at_floor(double dx, double x_norm) const { return dx <= kFloor * (1 + x_norm); }

 private:
  double tol_, step_tol_, target_;
};

// Throws InputError unless dt is positive and finite, tol >= 0 (or > 0 if required), the
// iteration and backtrack limits are at least 1 and 0.
void check_newton_options(double dt, double tol, bool tol_required, int max_iterations, int max_backtracks);

// How the iteration runs (the solvers' options map onto it).
struct NewtonLoop {
  int max_iterations = 30;
  int max_backtracks = 12;       // halvings of λ before the line search gives up
  bool line_search = true;       // false: every step full (λ = 1), accepted as it is
  // Simplified Newton: keep the factorisation while full steps are accepted and each correction is
  // at most reuse_contraction of the previous one; refactor otherwise.
  bool reuse = false;
  double reuse_contraction = 0.1;
  // One matrix for the whole solve (a quasi-Newton J̃, factored once): every correction trusted,
  // none fresh (the round-off floor test needs an exact Jacobian).
  bool fixed_jacobian = false;
  bool estimate_from_contraction = true;  // the θ test of StoppingRule
  // The θ test on the larger of the last two observed contractions (two needed): for an iteration
  // that converges linearly at a rate that varies from one correction to the next.
  bool steady_contraction = false;
  // Converged on a small correction: apply it (one more residual) instead of stopping before it, for
  // an iteration that contracts only linearly (its error is about that correction).
  bool apply_last_correction = false;
  // Converged on the contraction's estimate with a kept factorisation: one more correction from it (a
  // solve and a residual), for a residual at round-off (a free body's world momenta drift by what is left).
  bool correct_after_contraction = false;
};

// NoLcpSolution: the contact step's complementarity subproblem has none (contact_solver.hpp).
enum class Factor { Ok, Singular, NonFinite, NoLcpSolution };

template <class Problem>
SolveInfo newton_iterate(Problem& pb, const StoppingRule& rule, const NewtonLoop& loop) {
  SolveInfo info;
  info.residual_evaluations = 1;  // the Problem's residual at the first iterate
  auto finish = [&](SolveStatus status) {
    info.status = status;
    info.residual = pb.residual_norm();
    return info;
  };
  const bool keep = loop.reuse || loop.fixed_jacobian;
  bool reuse = keep;              // may the kept factorisation serve this iteration?
  double previous = INFINITY;     // ||dx||_inf of the previous full step
  double smallest = INFINITY;     // the smallest trusted correction so far
  double last_theta = 1;          // the contraction observed before (steady_contraction)
  for (;;) {
    if (!pb.finite()) return finish(SolveStatus::NonFinite);
    if (rule.residual_small(pb.stationarity()) && pb.feasible()) return finish(SolveStatus::Converged);
    if (info.iterations >= loop.max_iterations) return finish(SolveStatus::MaxIterations);
    // computeDirection: a fresh factorisation unless the kept one still serves.
    const bool fresh = !(reuse && pb.has_factor());
    if (fresh) {
      const Factor f = pb.factor();
      if (f != Factor::Ok)
        return finish(f == Factor::Singular        ? SolveStatus::SingularJacobian
                      : f == Factor::NoLcpSolution ? SolveStatus::LcpFailed
                                                   : SolveStatus::NonFinite);
      ++info.factorizations;
    }
    pb.direction();
    ++info.iterations;
    const bool exact = fresh && !loop.fixed_jacobian;  // dx from the Jacobian at this iterate
    if (!pb.direction_finite()) {
      if (!fresh && !loop.fixed_jacobian) {  // the kept Jacobian no longer fits: refactor here
        reuse = false;
        continue;
      }
      return finish(SolveStatus::NonFinite);
    }
    // stoppingCriteria: the next correction estimates the error of the iterate; stop without
    // applying it, so that the iterate and its outputs stay consistent. A kept factorisation
    // may give a small correction to a large residual: trusted once seen contracting.
    const double dx = pb.correction_norm();
    const bool trusted = fresh || loop.fixed_jacobian || dx <= loop.reuse_contraction * previous;
    if (!trusted) {  // a kept Jacobian contracting slowly: refactor here
      reuse = false;
      continue;
    }
    if (pb.feasible() && rule.correction_small(dx, smallest, pb.iterate_norm(), exact)) {
      if (loop.apply_last_correction) {
        pb.trial(1);
        ++info.residual_evaluations;
        pb.commit();
      }
      return finish(SolveStatus::Converged);
    }
    smallest = std::min(smallest, dx);
    if (!pb.accept_direction(dx, previous)) return finish(SolveStatus::LineSearchFailed);
    // tryStep: backtracking from the full step.
    double lambda = 1;
    bool accepted = false;
    for (int bt = 0; bt <= (loop.line_search ? loop.max_backtracks : 0); ++bt, lambda *= 0.5) {
      pb.trial(lambda);
      ++info.residual_evaluations;
      if (!loop.line_search || pb.sufficient_decrease(lambda)) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      if (!fresh && !loop.fixed_jacobian) {  // a kept Jacobian may mislead the search: retry with a fresh one
        reuse = false;
        continue;
      }
      info.residual_evaluations += pb.restore();
      // The exact correction says the iterate is within the floor of the solution, yet no
      // fraction of it reduces the residual: the residual is at its round-off floor.
      return finish(exact && pb.feasible() && rule.at_floor(dx, pb.iterate_norm()) ? SolveStatus::Converged
                                                                                   : SolveStatus::LineSearchFailed);
    }
    reuse = keep && (lambda == 1 || loop.fixed_jacobian);  // after a damped step the Jacobian is refactored
    const bool have_theta = lambda == 1 && previous < INFINITY;
    const double observed = have_theta ? dx / previous : 1;  // observed contraction
    const double theta = loop.steady_contraction ? std::max(observed, last_theta) : observed;
    last_theta = observed;
    previous = lambda == 1 ? dx : INFINITY;
    pb.commit();
    if (loop.estimate_from_contraction && have_theta && pb.finite() && pb.feasible() &&
        rule.contraction_small(theta, dx, pb.iterate_norm())) {
      if (loop.correct_after_contraction && pb.has_factor()) {
        pb.direction();
        if (pb.direction_finite()) {
          pb.trial(1);
          ++info.residual_evaluations;
          pb.commit();
        }
      }
      return finish(SolveStatus::Converged);
    }
  }
}

}  // namespace hovi
