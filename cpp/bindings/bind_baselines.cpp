// Bindings of the comparison baselines of the paper's Section 5 (hovi._core.baselines): the
// quasi-Newton of Lee et al. 2016, automatic differentiation, Hermite-Simpson collocation, and
// batch runners that time each solve in C++ (no Python overhead in the measurements).
#include <chrono>

#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/baselines/quasi_newton.hpp"
#include "hovi/errors.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

namespace {
using Clock = std::chrono::steady_clock;

// One trapezoidal step from each state (rows of Q0, QD0) by hovi's Newton or the quasi-Newton,
// from the same initial guess q + dt q̇ and with the same stopping rule.
py::dict one_step_batch(const PyModel& pm, double dt, const py::object& Q0, const py::object& QD0,
                        const std::string& method, double tol, int max_iterations) {
  const Model& model = pm.model;
  const int n = model.n();
  const MatX q0 = as_matrix(Q0, "q0", -1, n), qd0 = as_matrix(QD0, "qdot0", q0.rows(), n);
  const int N = static_cast<int>(q0.rows());
  if (method != "newton" && method != "quasi_newton") throw InputError("method must be 'newton' or 'quasi_newton'");
  Eigen::VectorXi iterations(N), converged(N);
  VecX seconds(N), residual(N);
  {
    py::gil_scoped_release release;
    Quadrature quad(1);
    SolverOptions opt;
    opt.tol = tol;
    opt.max_iterations = max_iterations;
    NewtonSolver newton(model, quad);
    QuasiNewtonOptions qopt;
    qopt.tol = tol;
    qopt.max_iterations = max_iterations;
    QuasiNewtonSolver qn(model, dt, qopt);
    Data data(model);
    MatX qc(n, 2), u(model.n_controls(), 2);
    u.setZero();
    VecX p_next(n);
    for (int k = 0; k < N; ++k) {
      const VecX q = q0.row(k).transpose(), qd = qd0.row(k).transpose();
      const VecX p = mass_matrix(model, data, q) * qd;
      qc.col(0) = q;
      qc.col(1) = q + dt * qd;
      const auto t0 = Clock::now();
      const SolveInfo info = method == "newton" ? newton.solve(model, quad, opt, p, u, dt, qc, p_next)
                                                : qn.solve(p, u, qc, p_next);
      seconds[k] = std::chrono::duration<double>(Clock::now() - t0).count();
      iterations[k] = info.iterations;
      converged[k] = info.converged();
      residual[k] = info.residual;
    }
  }
  py::dict d;
  d["converged"] = converged;
  d["iterations"] = iterations;
  d["seconds"] = seconds;
  d["residual"] = residual;
  return d;
}
}  // namespace

void bind_baselines(py::module_& m) {
  py::module_ b = m.def_submodule("baselines", "The paper's comparison baselines (Section 5)");
  b.def("one_step_batch", &one_step_batch, py::arg("model"), py::arg("dt"), py::arg("q0"), py::arg("qdot0"),
        py::arg("method"), py::arg("tol") = 1e-10, py::arg("max_iterations") = 100, R"doc(
One trapezoidal (s = 1) step from every state (rows of q0, qdot0; p0 = M(q0) qdot0) by 'newton'
(hovi's exact O(n) Newton with line search) or 'quasi_newton' (Lee et al. 2016), both from the
guess q0 + dt qdot0 and converged when ||r||_inf <= tol (1 + ||p0||_inf). Returns per-state
arrays converged, iterations, seconds (timed in C++), residual.
)doc");
}

}  // namespace hovi::py_bind
