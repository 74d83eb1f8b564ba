// The extension module hovi._baselines: the comparison baselines of the paper's Section 5, the
// quasi-Newton of Lee et al. 2016, automatic differentiation, Hermite-Simpson collocation, and
// batch runners that time each solve in C++ (no Python overhead in the measurements).
#include <chrono>
#include <cmath>
#include <mutex>

#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/baselines/autodiff_lagrangian.hpp"
#include "hovi/baselines/hermite_simpson.hpp"
#include "hovi/baselines/quasi_newton.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/step_continuation.hpp"
#include "hovi/parallel/parallel_for.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

using namespace pybind11::literals;  // "name"_a = value: the keyword arguments of the result dicts

namespace {
using Clock = std::chrono::steady_clock;

// One trapezoidal step from each state (rows of Q0, QD0) by hovi's Newton or the quasi-Newton,
// from the same initial guess q + dt q̇ and with the same stopping rule; or by continuation in
// the step length (step_continuation.hpp), alone or as the fallback of a failed Newton solve.
// The states are spread over `threads` C++ threads (parallel_for.hpp), each with its own solvers.
struct OneStepWorkspace {
  OneStepWorkspace(const Model& model, const Quadrature& quad, double dt, const QuasiNewtonOptions& qopt)
      : newton(model, quad), qn(model, dt, qopt), cws(model, quad), data(model), qc(model.n(), 2),
        u(MatX::Zero(model.n_controls(), 2)), p_next(model.n()) {}
  NewtonSolver newton;
  QuasiNewtonSolver qn;
  ContinuationWorkspace cws;
  Data data;
  MatX qc, u;
  VecX p_next;
};

StrDict one_step_batch(const PyModel& pm, double dt, const ArrayLike& Q0, const ArrayLike& QD0,
                        const std::string& method, double tol, int max_iterations, const OptInt& threads) {
  const Model& model = pm.model;
  const int n = model.n();
  const MatX q0 = as_matrix(Q0, "q0", -1, n), qd0 = as_matrix(QD0, "qdot0", q0.rows(), n);
  const int N = static_cast<int>(q0.rows());
  const bool newton_first = method == "newton" || method == "newton+continuation";
  const bool continuation = method == "continuation" || method == "newton+continuation";
  if (!newton_first && !continuation && method != "quasi_newton")
    throw InputError("method must be 'newton', 'quasi_newton', 'continuation' or 'newton+continuation'");
  const int nthreads = thread_count(threads_arg(threads));
  Eigen::VectorXi iterations = Eigen::VectorXi::Zero(N), converged = iterations, residual_evaluations = iterations;
  std::vector<std::string> status(N, "error"), errors;
  VecX seconds = VecX::Zero(N), residual = VecX::Constant(N, NAN), h_reached = VecX::Constant(N, NAN);
  MatX q_next = MatX::Constant(N, n, NAN);
  {
    py::gil_scoped_release release;
    const Quadrature quad(1);
    SolverOptions opt;
    opt.tol = tol;
    opt.max_iterations = max_iterations;
    opt.reuse = Reuse::Never;  // the paper's exact Newton: a fresh recursive Jacobian every iteration
    opt.direction = Direction::Recursive;
    QuasiNewtonOptions qopt;
    qopt.tol = tol;
    qopt.max_iterations = max_iterations;
    std::vector<std::unique_ptr<OneStepWorkspace>> workspaces(nthreads);  // made by the thread that uses it
    errors = parallel_for(N, nthreads, [&](int k, int thread) {
      auto& w = workspaces[thread];
      if (!w) w = std::make_unique<OneStepWorkspace>(model, quad, dt, qopt);
      MatX& qc = w->qc;
      const VecX q = q0.row(k).transpose(), qd = qd0.row(k).transpose();
      const VecX p = mass_matrix(model, w->data, q) * qd;
      qc.col(0) = q;
      qc.col(1) = q + dt * qd;
      const auto t0 = Clock::now();
      SolveInfo info;
      if (newton_first) info = w->newton.solve(model, quad, opt, p, w->u, dt, qc, w->p_next);
      else if (!continuation) info = w->qn.solve(p, w->u, qc, w->p_next);
      if (continuation && !info.converged()) {
        const SolveInfo first = info;
        ContinuationReport rep;
        info = step_continuation(w->newton, w->cws, model, quad, opt, p, w->u, dt, qc, w->p_next, {}, &rep);
        h_reached[k] = rep.h_reached;
        info.iterations += first.iterations;
        info.factorizations += first.factorizations;
        info.residual_evaluations += first.residual_evaluations;
      }
      seconds[k] = std::chrono::duration<double>(Clock::now() - t0).count();
      status[k] = to_string(info.status);
      residual_evaluations[k] = info.residual_evaluations;
      iterations[k] = info.iterations;
      converged[k] = info.converged();
      residual[k] = info.residual;
      q_next.row(k) = qc.col(1).transpose();
    });
  }
  StrDict d("converged"_a = converged, "iterations"_a = iterations, "residual_evaluations"_a = residual_evaluations,
            "status"_a = status, "h_reached"_a = h_reached, "seconds"_a = seconds, "residual"_a = residual,
            "q_next"_a = q_next, "errors"_a = error_list(errors));
  return d;
}

// Mean time per call (seconds, at least `min_seconds` of repetitions) of f.
template <class F>
double time_call(F&& f, double min_seconds) {
  f();
  int reps = 0;
  const auto t0 = Clock::now();
  double elapsed = 0;
  while (elapsed < min_seconds || reps < 1) {
    f();
    ++reps;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return elapsed / reps;
}

// Paper Fig. 3: per-state times of the DEL evaluation, the Newton direction and D^2 L_d, by
// hovi's recursive algorithms ('recursive') or automatic differentiation ('autodiff'), at
// control points q + c^a dt q̇ for every state.
StrDict fig3_batch(const PyModel& pm, int s, double dt, const ArrayLike& Q0, const ArrayLike& QD0,
                    const std::string& method, double min_seconds) {
  const Model& model = pm.model;
  const int n = model.n();
  const MatX q0 = as_matrix(Q0, "q0", -1, n), qd0 = as_matrix(QD0, "qdot0", q0.rows(), n);
  const int N = static_cast<int>(q0.rows());
  if (method != "recursive" && method != "autodiff") throw InputError("method must be 'recursive' or 'autodiff'");
  VecX t_eval(N), t_dir(N), t_d2(N);
  {
    py::gil_scoped_release release;
    const Quadrature quad(s);
    DelWorkspace del(model, quad);
    NewtonWorkspace nws(model, quad);
    DelJacobianWorkspace jws(model, quad);
    std::unique_ptr<AutodiffDel> ad;
    if (method == "autodiff") ad = std::make_unique<AutodiffDel>(model, quad, dt);
    MatX qc(n, s + 1), r(n, s), dq(n, s), H((s + 1) * n, (s + 1) * n), u(model.n_controls(), s + 1);
    u.setZero();
    VecX p(n), p_next(n);
    for (int k = 0; k < N; ++k) {
      for (int a = 0; a <= s; ++a) qc.col(a) = q0.row(k).transpose() + quad.c[a] * dt * qd0.row(k).transpose();
      p = qd0.row(k).transpose();
      if (ad) {
        t_eval[k] = time_call([&] { ad->residual(qc, p, u, r, p_next); }, min_seconds);
        t_dir[k] = time_call([&] { ad->newton_direction(qc, p, u, dq); }, min_seconds);
        t_d2[k] = time_call([&] { ad->d2Ld(qc, H); }, min_seconds);
      } else {
        t_eval[k] = time_call([&] { del_residual(model, quad, del, qc, p, u, dt, r, p_next); }, min_seconds);
        del_residual(model, quad, del, qc, p, u, dt, r, p_next);
        t_dir[k] = time_call([&] { newton_direction(model, quad, del, nws, r, dq); }, min_seconds);
        t_d2[k] = time_call([&] { dlagrangian_hessian(model, quad, jws, qc, dt, H); }, min_seconds);
      }
    }
  }
  StrDict d;
  d["del_residual"] = t_eval;
  d["newton_direction"] = t_dir;
  d["d2Ld"] = t_d2;
  return d;
}
// A baseline object with a watch on the model it copied and a lock: a baseline keeps one
// workspace, so concurrent calls on one object take turns (one object per thread runs in
// parallel). Lock only with the GIL released (or in calls that never release it).
template <class B>
struct PyBaseline {
  template <class... Args>
  PyBaseline(std::shared_ptr<const PyModel> m, const char* name, Args&&... args)
      : b(m->model, std::forward<Args>(args)...), watch(std::move(m), name) {}
  B b;
  ModelWatch watch;
  std::mutex mutex;
};
template <class B>
B& checked(PyBaseline<B>& self) {
  self.watch.check();
  return self.b;
}
using PyHermiteSimpson = PyBaseline<HermiteSimpson>;
using PyAutodiffDel = PyBaseline<AutodiffDel>;
}  // namespace

void bind_baselines(py::module_& b) {
  b.def("one_step_batch", &one_step_batch, py::arg("model"), py::arg("dt"), py::arg("q0"), py::arg("qdot0"),
        py::arg("method"), py::arg("tol") = 1e-10, py::arg("max_iterations") = 100, py::arg("threads") = py::none(), R"doc(
One trapezoidal (s = 1) step from every state (rows of q0, qdot0, (N, n); p0 = M(q0) qdot0) by 'newton'
(hovi's exact O(n) Newton with line search) or 'quasi_newton' (Lee et al. 2016), both from the
guess q0 + dt qdot0, or by 'continuation' in the step length (the step on the solution branch
continuously connected to q0, or the status 'continuation_stalled' when that branch turns back
before dt), or 'newton+continuation' (continuation when Newton fails); all converged when
||r||_inf <= tol (1 + ||p0||_inf). Returns per-state arrays converged, iterations (Newton
directions), residual_evaluations, status, seconds (timed in C++), residual, q_next (the last
iterate; after a stalled continuation the last point of the branch, at h_reached < dt),
h_reached (continuation: how far in the step length the branch went; NaN otherwise) and errors
(None, or the message of an exception a state raised: its status is 'error'). The states are
spread over `threads` C++ threads (None: HOVI_NUM_THREADS or every core; the results do not
depend on it, the times per solve may, as the threads share the machine).
)doc");
  b.def("fig3_batch", &fig3_batch, py::arg("model"), py::arg("s"), py::arg("dt"), py::arg("q0"), py::arg("qdot0"),
        py::arg("method"), py::arg("min_seconds") = 0.002, R"doc(
Per-state times (N,) (seconds, timed in C++; states: rows of q0, qdot0 (N, n)) of the DEL evaluation, the Newton direction and D^2 L_d by
'recursive' (hovi: Algorithm 1, A.1/A.2, Algorithms 2/3 + chain rule) or 'autodiff' (Eigen
AutoDiffScalar on a scalar-templated Lagrangian, dense LU), at control points q + c^a dt qdot.
)doc");
  py::class_<PyHermiteSimpson>(b, "HermiteSimpson", R"doc(
Hermite-Simpson direct collocation as an implicit simulator (the paper's Sec. 5.3 baseline): the
implicit formulation with the end and midpoint accelerations as unknowns and inverse-dynamics
defects, Newton with an analytic dense Jacobian (RNEA derivatives) and LU; state (q, v).
)doc")
      .def(py::init([](std::shared_ptr<PyModel> m, double dt, double tol, int max_iterations, bool reuse_jacobian) {
             HermiteSimpsonOptions opt;
             opt.tol = tol;
             opt.max_iterations = max_iterations;
             opt.reuse_jacobian = reuse_jacobian;
             return new PyHermiteSimpson(std::move(m), "baselines.HermiteSimpson", dt, opt);
           }),
           py::arg("model"), py::arg("dt"), py::arg("tol") = 1e-10, py::arg("max_iterations") = 30,
           py::arg("reuse_jacobian") = true, "The simulator with step dt on a copy of `model`.")
      .def("rollout", [](PyHermiteSimpson& self, const ArrayLike& q0, const ArrayLike& v0, int steps) {
            HermiteSimpson& hs = checked(self);
            const int n = hs.model().n();
            const VecX q = as_vector(q0, "q0", n), v = as_vector(v0, "v0", n);
            if (steps < 0) throw InputError("steps must be non-negative");
            HermiteSimpsonRollout r;
            double seconds;
            {
              py::gil_scoped_release release;
              std::lock_guard<std::mutex> lock(self.mutex);
              const auto t0 = Clock::now();
              r = hs.rollout(q, v, steps);
              seconds = std::chrono::duration<double>(Clock::now() - t0).count();
            }
            StrDict d;
            d["q"] = MatX(r.q.topRows(r.steps + 1));
            d["v"] = MatX(r.v.topRows(r.steps + 1));
            d["iterations"] = Eigen::VectorXi(r.iterations.head(std::min<int>(steps, r.steps + 1)));
            py::list st;
            for (SolveStatus x : r.status) st.append(to_string(x));
            d["status"] = st;
            d["steps"] = r.steps;
            d["seconds"] = seconds;
            return d;
          }, py::arg("q0"), py::arg("v0"), py::arg("steps"), R"doc(
Simulate `steps` steps from q0, v0 (n,) in C++ (GIL released); stops at a failed solve. Returns a
dict: q, v (K+1, n), iterations, status (per step), steps K, seconds.
)doc");
  py::class_<PyAutodiffDel>(b, "AutodiffDel", "The automatic-differentiation baseline (dense, O(n^2)..O(n^3)).")
      .def(py::init([](std::shared_ptr<PyModel> m, int s, double dt) {
             return new PyAutodiffDel(std::move(m), "baselines.AutodiffDel", Quadrature(s), dt);
           }),
           py::arg("model"), py::arg("s"), py::arg("dt"), "The order-2s DEL equations with step dt on a copy of `model`.")
      .def("residual", [](PyAutodiffDel& self, const ArrayLike& qc, const ArrayLike& p) {
            AutodiffDel& ad = checked(self);  // holds the GIL: calls never overlap
            const int n = ad.n(), s = ad.s();
            MatX r(n, s), u = MatX::Zero(0, s + 1);
            VecX pn(n);
            ad.residual(as_matrix(qc, "control_points", s + 1, n).transpose(), as_vector(p, "p", n), u, r, pn);
            return py::make_tuple(MatX(r.transpose()), pn);
          }, py::arg("control_points"), py::arg("p"),
          "control_points (s+1, n), p (n,); returns (r (s, n), p_next (n,)), by automatic differentiation.")
      .def("newton_direction", [](PyAutodiffDel& self, const ArrayLike& qc, const ArrayLike& p) {
            AutodiffDel& ad = checked(self);  // holds the GIL: calls never overlap
            const int n = ad.n(), s = ad.s();
            MatX dq(n, s), u = MatX::Zero(0, s + 1);
            ad.newton_direction(as_matrix(qc, "control_points", s + 1, n).transpose(), as_vector(p, "p", n), u, dq);
            return MatX(dq.transpose());
          }, py::arg("control_points"), py::arg("p"),
          "control_points (s+1, n), p (n,); returns the Newton direction dq (s, n) (dense LU of the AD Jacobian).")
      .def("d2Ld", [](PyAutodiffDel& self, const ArrayLike& qc) {
            AutodiffDel& ad = checked(self);  // holds the GIL: calls never overlap
            const int n = ad.n(), s = ad.s();
            MatX H((s + 1) * n, (s + 1) * n);
            ad.d2Ld(as_matrix(qc, "control_points", s + 1, n).transpose(), H);
            return H;
          }, py::arg("control_points"), "control_points (s+1, n); returns D^2 L_d, ((s+1) n, (s+1) n), by automatic differentiation.");
}

}  // namespace hovi::py_bind

PYBIND11_MODULE(_baselines, m) {
  m.doc() = "The paper's comparison baselines (Section 5), apart from the hovi._core product";
  pybind11::module_::import("hovi._core");  // Model, the exceptions and their translators
  hovi::py_bind::bind_baselines(m);
}
