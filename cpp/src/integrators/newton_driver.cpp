#include "hovi/integrators/newton_driver.hpp"

#include <string>

#include "hovi/errors.hpp"

namespace hovi {

const char* to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::Converged: return "converged";
    case SolveStatus::MaxIterations: return "max_iterations";
    case SolveStatus::LineSearchFailed: return "line_search_failed";
    case SolveStatus::SingularJacobian: return "singular_jacobian";
    case SolveStatus::NonFinite: return "non_finite";
    case SolveStatus::ContinuationStalled: return "continuation_stalled";
    case SolveStatus::LcpFailed: return "lcp_failed";
    case SolveStatus::ControllerFailed: return "controller_failed";
  }
  return "unknown";
}

void check_newton_options(double dt, double tol, bool tol_required, int max_iterations, int max_backtracks) {
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("dt must be positive and finite, got " + std::to_string(dt));
  if (tol_required && !(tol > 0)) throw InputError("tol must be positive");
  if (!tol_required && (!(tol >= 0) || !std::isfinite(tol))) throw InputError("tol must be zero (off) or positive");
  if (max_iterations < 1) throw InputError("max_iterations must be at least 1");
  if (max_backtracks < 0) throw InputError("max_backtracks must be non-negative");
}

}  // namespace hovi
