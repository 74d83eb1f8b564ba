// Bindings of the control layer (hovi._core.control): Riccati equations, the velocity state map and
// closed-loop runs in C++. The Pythonic layer is python/hovi/control/.
#include <chrono>
#include <exception>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hovi/control/box_fddp.hpp"
#include "hovi/control/closed_loop.hpp"
#include "hovi/control/mpc.hpp"
#include "hovi/control/riccati.hpp"
#include "hovi/control/state_map.hpp"
#include "hovi/errors.hpp"
#include "py_integrator.hpp"

namespace hovi::py_bind {

using namespace pybind11::literals;  // "name"_a = value: the keyword arguments of the result dicts
namespace {

// (K, r, c) array -> K matrices r x c
std::vector<MatX> matrices(const ArrayLike& x, const char* name, long rows, long cols) {
  const RealArray a = real_array(x, name);
  if (a.ndim() == 2 && a.shape(0) == rows && a.shape(1) == cols) return {as_matrix(x, name, rows, cols)};
  if (a.ndim() != 3 || (rows >= 0 && a.shape(1) != rows) || (cols >= 0 && a.shape(2) != cols))
    throw InputError(std::string(name) + " must have shape (K, " + std::to_string(rows) + ", " + std::to_string(cols) + ")");
  std::vector<MatX> out(a.shape(0));
  auto r = a.unchecked<3>();
  for (py::ssize_t k = 0; k < a.shape(0); ++k) {
    out[k].resize(a.shape(1), a.shape(2));
    for (py::ssize_t i = 0; i < a.shape(1); ++i)
      for (py::ssize_t j = 0; j < a.shape(2); ++j) out[k](i, j) = r(k, i, j);
  }
  return out;
}

// pushes: per run, a list of (step, body, point (3,), impulse (3,))
std::vector<std::vector<Push>> pushes_arg(const py::list& runs) {
  std::vector<std::vector<Push>> out;
  for (const py::handle& run : runs) {
    std::vector<Push> items;
    for (const py::handle& p : run.cast<py::list>()) {
      const py::tuple t = p.cast<py::tuple>();
      if (t.size() != 4 && t.size() != 5) throw InputError("a push is (step, body, point (3,), impulse (3,)[, angular (3,)])");
      items.push_back({t[0].cast<int>(), t[1].cast<int>(), as_vector(t[2], "push point", 3), as_vector(t[3], "push impulse", 3),
                       t.size() == 5 ? Vec3(as_vector(t[4], "push angular impulse", 3)) : Vec3(Vec3::Zero())});
    }
    out.push_back(std::move(items));
  }
  return out;
}

Policy policy_arg(const ArrayLike& x_ref, const ArrayLike& u_ref, const ArrayLike& gains, const ArrayLike& lower,
                  const ArrayLike& upper) {
  Policy p;
  const RealArray g = real_array(gains, "gains");
  if (g.ndim() != 3) throw InputError("gains must have shape (S, m, 2n)");
  p.K = matrices(gains, "gains", g.shape(1), g.shape(2));
  const long S = long(p.K.size());
  p.x_ref = as_matrix(x_ref, "x_ref", S, -1);
  p.u_ref = as_matrix(u_ref, "u_ref", S, -1);
  const RealArray lo = real_array(lower, "lower"), hi = real_array(upper, "upper");
  p.lower = Eigen::Map<const VecX>(lo.data(), lo.size());
  p.upper = Eigen::Map<const VecX>(hi.data(), hi.size());
  return p;
}

// B closed-loop runs (closed_loop_batch) on the plants' integrators, as rollout dicts.
py::tuple run_batch(const py::list& plants, const Policy& policy, const py::list& pushes, const MatX& Q0, const MatX& P0,
                    int steps, int threads) {
  std::vector<const GalerkinIntegrator*> ps;
  for (const py::handle& h : plants) ps.push_back(&h.cast<const PyIntegrator&>().integ());
  const auto push = pushes_arg(pushes);
  std::vector<Rollout> out;
  std::vector<std::string> errors;
  std::vector<double> seconds(Q0.rows());
  {
    py::gil_scoped_release release;
    const auto t0 = std::chrono::steady_clock::now();
    errors = closed_loop_batch(ps, policy, push, Q0, P0, steps, out, threads);
    seconds.assign(Q0.rows(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  py::list items;
  for (std::size_t b = 0; b < out.size(); ++b)
    items.append(errors[b].empty() ? py::object(rollout_dict(out[b], seconds[b] / double(out.size()))) : py::none());
  return py::make_tuple(items, error_list(errors));
}

// A ShootingProblem with the Integrator it steps kept alive (py::keep_alive) and its model watched.
class PyShootingProblem {
 public:
  PyShootingProblem(const PyIntegrator& integ, int N, const VecX& x0, std::vector<SampleCost> costs, const VecX& lo,
                    const VecX& hi, double smoothing)
      : integ_(integ), core_(integ.integ(), N, x0, std::move(costs), lo, hi, smoothing) {}
  ShootingProblem& core() {
    integ_.integ();  // raises once the model changed
    return core_;
  }

 private:
  const PyIntegrator& integ_;
  ShootingProblem core_;
};

std::vector<SampleCost> sample_costs(const py::list& terms, int n, int m) {
  std::vector<SampleCost> out;
  for (const py::handle& h : terms) {
    const py::dict d = h.cast<py::dict>();
    SampleCost c;
    c.terminal = d["terminal"].cast<bool>();
    c.Wq = as_matrix(d["Wq"], "Wq", -1, n);
    const long rows = c.Wq.rows();
    c.q_ref = as_matrix(d["q_ref"], "q_ref", rows, n);
    c.Wv = as_matrix(d["Wv"], "Wv", rows, n);
    c.v_ref = as_matrix(d["v_ref"], "v_ref", rows, n);
    c.R = as_matrix(d["R"], "R", rows, m);
    c.u_ref = as_matrix(d["u_ref"], "u_ref", rows, m);
    out.push_back(std::move(c));
  }
  return out;
}

// A StepCosts of a Python callable fun(kind, control_points (N, s+1, n), us (N, m)): kind "value"
// returns the total, "derivatives" (g (N, (s+1) n + m), H (N, (s+1) n + m, (s+1) n + m)). Called with
// the GIL taken; a Python exception is kept (error) and ends the solve.
class PyStepCosts : public StepCosts {
 public:
  PyStepCosts(py::object fun, int n, int m, int S1) : fun_(std::move(fun)), n_(n), m_(m), S1_(S1) {}
  double value(const std::vector<MatX>& qc, const std::vector<VecX>& us) override {
    py::gil_scoped_acquire gil;
    try {
      return fun_("value", pack(qc), pack_u(us)).cast<double>();
    } catch (py::error_already_set&) {
      error = std::current_exception();
      throw std::runtime_error("the user cost raised");
    }
  }
  void derivatives(const std::vector<MatX>& qc, const std::vector<VecX>& us, std::vector<VecX>& g,
                   std::vector<MatX>& H) override {
    py::gil_scoped_acquire gil;
    try {
      const py::tuple out = fun_("derivatives", pack(qc), pack_u(us));
      const long N = long(qc.size()), z = S1_ * n_ + m_;
      const MatX G = as_matrix(out[0], "user cost gradient", N, z);
      const std::vector<MatX> Hs = matrices(out[1], "user cost Hessian", z, z);
      if (long(Hs.size()) != N) throw InputError("the user cost Hessian must have one block per step");
      g.resize(N);
      H = Hs;
      for (long k = 0; k < N; ++k) g[k] = G.row(k).transpose();
    } catch (py::error_already_set&) {
      error = std::current_exception();
      throw std::runtime_error("the user cost raised");
    }
  }
  std::exception_ptr error;

 private:
  py::array_t<double> pack(const std::vector<MatX>& qc) const {
    py::array_t<double> a({long(qc.size()), long(S1_), long(n_)});
    auto w = a.mutable_unchecked<3>();
    for (std::size_t k = 0; k < qc.size(); ++k)
      for (int c = 0; c < S1_; ++c)
        for (int i = 0; i < n_; ++i) w(k, c, i) = qc[k](i, c);
    return a;
  }
  py::array_t<double> pack_u(const std::vector<VecX>& us) const {
    py::array_t<double> a({long(us.size()), long(m_)});
    auto w = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < us.size(); ++k)
      for (int i = 0; i < m_; ++i) w(k, i) = us[k][i];
    return a;
  }
  py::object fun_;
  int n_, m_, S1_;
};

StrDict fddp_dict(const FddpResult& r) {
  StrDict d("xs"_a = r.xs, "us"_a = r.us, "control_points"_a = r.control_points, "impulses"_a = r.impulses,
            "K"_a = stack(r.K), "cost"_a = r.cost, "stop"_a = r.stop, "gaps"_a = r.gaps,
            "iterations"_a = r.iterations, "converged"_a = r.converged, "feasible"_a = r.feasible,
            "status"_a = r.status);
  MatX trace(r.trace.size(), 5);
  for (std::size_t i = 0; i < r.trace.size(); ++i)
    trace.row(i) << r.trace[i].cost, r.trace[i].stop, r.trace[i].step, r.trace[i].reg, r.trace[i].gaps;
  d["trace"] = trace;
  d["seconds"] = r.seconds;
  return d;
}

}  // namespace

void bind_control(py::module_& parent) {
  py::module_ m = parent.def_submodule("control", "Riccati equations and closed-loop runs in C++ (hovi.control)");
  m.def("discrete_are", [](const ArrayLike& A, const ArrayLike& B, const ArrayLike& Q, const ArrayLike& R) {
        const MatX a = as_matrix(A, "A", -1, -1);
        const MatX b = as_matrix(B, "B", a.rows(), -1);
        MatX P, K;
        int it = 0;
        discrete_are(a, b, as_matrix(Q, "Q", a.rows(), a.rows()), as_matrix(R, "R", b.cols(), b.cols()), P, K, &it);
        return py::make_tuple(P, K, it);
      }, py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), R"doc(
The stabilising solution of the discrete algebraic Riccati equation for A (n, n), B (n, m), Q (n, n),
R (m, m) (stage cost x^T Q x + u^T R u): returns (P (n, n), K (m, n), doublings), u = -K x.
)doc");
  m.def("backward_riccati", [](const ArrayLike& A, const ArrayLike& B, const ArrayLike& Q, const ArrayLike& R,
                               const ArrayLike& QN) {
        const std::vector<MatX> a = matrices(A, "A", -1, -1);
        if (a.empty()) throw InputError("A must hold at least one stage");
        const long n = a[0].rows();
        const std::vector<MatX> b = matrices(B, "B", n, -1);
        const long m = b.empty() ? 0 : b[0].cols();
        std::vector<MatX> K, P;
        backward_riccati(a, b, matrices(Q, "Q", n, n), matrices(R, "R", m, m), as_matrix(QN, "QN", n, n), K, P);
        return py::make_tuple(stack(K), stack(P));
      }, py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), py::arg("QN"), R"doc(
Finite-horizon LQR: A (N, n, n), B (N, n, m), Q (n, n) or (N, n, n), R (m, m) or (N, m, m), QN (n, n);
returns (K (N, m, n), P (N+1, n, n)), u^k = -K^k x^k, cost-to-go x^T P^k x.
)doc");
  m.def("velocity_state_map", [](const PyModel& model, const ArrayLike& q, const ArrayLike& p) {
        const MatX Q = as_matrix(q, "q", -1, model.model.nq()), P = as_matrix(p, "p", Q.rows(), model.model.n());
        Data data(model.model);
        std::vector<MatX> out(Q.rows());
        for (long k = 0; k < Q.rows(); ++k) velocity_state_map(model.model, data, Q.row(k).transpose(), P.row(k).transpose(), out[k]);
        return stack(out);
      }, py::arg("model"), py::arg("q"), py::arg("p"), R"doc(
T = d(q, q̇)/d(q, p) (K, 2n, 2n) at states q (K, nq), p (K, n), q̇ = M(q)^{-1} p: a cost x_user^T W x_user on
(q, q̇) is x^T (T^T W T) x on the integrator's state x = (q, p) (a free base: q's part a tangent vector).
)doc");
  py::class_<PyShootingProblem>(m, "ShootingProblem", R"doc(
The VI as the dynamics of an optimal control problem (control/shooting_problem.hpp): N steps of an
Integrator from x0 = (q, p) (2n,), held controls within u_lower, u_upper (m,), and quadratic cost terms
on the steps' control points (hovi.trajopt.FDDP builds it from a Problem).
)doc")
      .def(py::init([](const PyIntegrator& integ, int N, const ArrayLike& x0, const py::list& costs,
                       const ArrayLike& u_lower, const ArrayLike& u_upper, double smoothing) {
             const int n = integ.n(), m = integ.m();
             const RealArray lo = real_array(u_lower, "u_lower"), hi = real_array(u_upper, "u_upper");
             const VecX x = as_vector(x0, "x0", 2 * n);
             const VecX l = Eigen::Map<const VecX>(lo.data(), lo.size()), h = Eigen::Map<const VecX>(hi.data(), hi.size());
             return std::make_unique<PyShootingProblem>(integ, N, x, sample_costs(costs, n, m), l, h, smoothing);
           }),
           py::keep_alive<1, 2>(), py::arg("integrator"), py::arg("N"), py::arg("x0"), py::arg("costs"),
           py::arg("u_lower"), py::arg("u_upper"), py::arg("smoothing") = 0.0, R"doc(
integrator: a _core.Integrator; with contacts (s = 1) the problem shoots through contact with its
Jacobians held (smoothing = 0) or smoothed (smoothing > 0, contact_jacobians.hpp).
costs: a list of dicts, each a term with `terminal` (bool) and diagonal weights and references per sample,
Wq, q_ref, Wv, v_ref (rows, n), R, u_ref (rows, m): rows = S (s+1) for a running term (S stages; step k
uses stage min(offset + k, S - 1)), 1 for a terminal term (the horizon's last sample).
)doc")
      .def_property("x0", [](PyShootingProblem& p) { return VecX(p.core().x0()); },
                    [](PyShootingProblem& p, const ArrayLike& x) { p.core().set_x0(as_vector(x, "x0", p.core().nx())); },
                    "The initial state (q, p), (2n,).")
      .def_property("offset", [](PyShootingProblem& p) { return p.core().offset; },
                    [](PyShootingProblem& p, int k) {
                      if (k < 0) throw InputError("offset must be >= 0");
                      p.core().offset = k;
                    }, "The stage of the cost terms' references that step 0 uses.")
      .def("stage_cost", [](PyShootingProblem& p, int k, const ArrayLike& cps, const ArrayLike& u) {
            ShootingProblem& c = p.core();
            const int n = c.nx() / 2;
            return c.stage_cost(k, as_matrix(cps, "control_points", c.s() + 1, n).transpose(), as_vector(u, "u", c.nu()));
          }, py::arg("k"), py::arg("control_points"), py::arg("u"),
          "The cost l^k of step k at its control points (s+1, n) with held controls u (m,).")
      .def("derivatives", [](PyShootingProblem& p, int k, const ArrayLike& cps, const ArrayLike& u,
                             const OptArrayLike& impulses) {
            ShootingProblem& c = p.core();
            const int n = c.nx() / 2;
            StageDerivatives d;
            const VecX z = impulses.is_none() ? VecX::Zero(c.impulses()) : as_vector(impulses, "impulses", c.impulses());
            if (!c.derivatives(k, as_matrix(cps, "control_points", c.s() + 1, n).transpose(), as_vector(u, "u", c.nu()), z, d))
              throw InputError("the step's DEL Jacobian is singular");
            StrDict out("A"_a = d.A, "B"_a = d.B, "lx"_a = d.lx, "lu"_a = d.lu, "lxx"_a = d.lxx, "luu"_a = d.luu,
                        "lux"_a = d.lux);
            return out;
          }, py::arg("k"), py::arg("control_points"), py::arg("u"), py::arg("impulses") = py::none(), R"doc(
Step k's derivatives (through contact: at the step's impulses) at converged control points (s+1, n) with held u (m,): A (2n, 2n), B (2n, m), the cost
gradient lx (2n,), lu (m,) and Gauss-Newton Hessian lxx, luu, lux.
)doc")
      .def("solve", [](PyShootingProblem& p, const OptArrayLike& xs, const OptArrayLike& us, int max_iterations, double tol,
                       int threads, const std::optional<py::function>& user_cost) {
            ShootingProblem& c = p.core();
            const MatX X = xs.is_none() ? MatX() : as_matrix(xs, "xs", c.N() + 1, c.nx());
            const MatX U = us.is_none() ? MatX() : as_matrix(us, "us", c.N(), c.nu());
            FddpOptions opt;
            opt.max_iterations = max_iterations;
            opt.tol = tol;
            opt.threads = threads_arg(py::int_(threads));
            std::unique_ptr<PyStepCosts> extra;
            if (user_cost) extra = std::make_unique<PyStepCosts>(*user_cost, c.nx() / 2, c.nu(), c.s() + 1);
            c.extra = extra.get();
            BoxFddp solver(c, opt);
            FddpResult r;
            try {
              py::gil_scoped_release release;
              r = solver.solve(X, U);
            } catch (...) {
              c.extra = nullptr;
              if (extra && extra->error) std::rethrow_exception(extra->error);
              throw;
            }
            c.extra = nullptr;
            return fddp_dict(r);
          }, py::arg("xs") = py::none(), py::arg("us") = py::none(), py::arg("max_iterations") = 500,
          py::arg("tol") = 1e-9, py::arg("threads") = 1, py::arg("user_cost") = py::none(), R"doc(
Box-FDDP (control/box_fddp.hpp) from xs (N+1, 2n) (None: the rollout of us from x0) and us (N, m) (None:
zeros), in C++ with the GIL released. user_cost: None, or fun(kind, control_points (N, s+1, n), us (N, m))
for costs computed in Python, one call per rollout ("value": the total) and per linearisation
("derivatives": g (N, (s+1) n + m) and the Gauss-Newton Hessian H (N, (s+1) n + m, (s+1) n + m) in each
step's (vec(q^{k,0..s}) by points, u^k)); an exception it raises is raised. Returns a dict: xs, us,
control_points (N, (s+1) n), K (N, m, 2n) (u = us + K (x - xs)), cost, stop, gaps, iterations, converged,
feasible, status, trace (iterations, 5: cost, stop, step, regularisation, gaps), seconds.
)doc");
  m.def("mpc", [](const PyIntegrator& plant, PyShootingProblem& problem, const ArrayLike& q0, const ArrayLike& p0, int steps,
                  int period, int max_iterations, double tol, const py::list& pushes, const OptArrayLike& us_init) {
        ShootingProblem& pb = problem.core();
        const int n = pb.nx() / 2;
        const VecX q = as_vector(q0, "q0", n), mom = as_vector(p0, "p0", n);
        const MatX U = us_init.is_none() ? MatX() : as_matrix(us_init, "us_init", pb.N(), pb.nu());
        if (steps < 0) throw InputError("steps must be non-negative");
        FddpOptions opt;
        opt.max_iterations = max_iterations;
        opt.tol = tol;
        const auto push = pushes_arg(pushes);
        const std::vector<Push> none;
        const std::vector<Push>& mine = push.empty() ? none : push[0];
        const GalerkinIntegrator& integ = plant.integ();
        if (std::abs(integ.dt() - pb.integrator().dt()) > 1e-12 * pb.integrator().dt())
          throw InputError("the plant's dt must be the controller's (the problem's T / N)");
        check_pushes(integ.model(), mine);
        MpcHook hook(pb, opt, period, integ.model(), mine, U);
        Rollout r;
        double seconds;
        {
          py::gil_scoped_release release;
          const auto t0 = std::chrono::steady_clock::now();
          r = integ.rollout(q, mom, steps, MatX(), StepHistory(), &hook);
          seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        StrDict d = rollout_dict(r, seconds);
        const MpcStats& st = hook.stats();
        d["solve_seconds"] = VecX(Eigen::Map<const VecX>(st.solve_seconds.data(), st.solve_seconds.size()));
        d["solve_iterations"] = Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(st.iterations.data(), st.iterations.size()));
        d["solve_converged"] = Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(st.converged.data(), st.converged.size()));
        d["solve_failure"] = hook.failure().empty() ? py::object(py::none()) : py::object(py::str(hook.failure()));
        return d;
      }, py::arg("plant"), py::arg("problem"), py::arg("q0"), py::arg("p0"), py::arg("steps"), py::arg("period"),
      py::arg("max_iterations"), py::arg("tol"), py::arg("pushes"), py::arg("us_init") = py::none(), R"doc(
`steps` steps of plant (a _core.Integrator, with or without contacts, with the problem's dt) from q0, p0
(n,) under MPC (control/mpc.hpp): FDDP on `problem` re-solved every `period` steps (at most max_iterations,
tol), warm-started from the last plan shifted; pushes: a list with one list of (step, body, point,
impulse). Returns the plant's rollout dict with controls, and per solve solve_seconds, solve_iterations,
solve_converged; a solve that fails from the plant's state ends the run (status 'controller_failed'),
solve_failure its message (else None).
)doc");
  m.def("closed_loop", [](const py::list& plants, const ArrayLike& x_ref, const ArrayLike& u_ref, const ArrayLike& gains,
                          const ArrayLike& lower, const ArrayLike& upper, const py::list& pushes, const ArrayLike& q0s,
                          const ArrayLike& p0s, int steps, const OptInt& threads) {
        if (plants.empty()) throw InputError("give at least one plant");
        const Policy policy = policy_arg(x_ref, u_ref, gains, lower, upper);
        const MatX Q0 = as_matrix(q0s, "q0s", -1, -1), P0 = as_matrix(p0s, "p0s", Q0.rows(), -1);
        if (steps < 0) throw InputError("steps must be non-negative");
        const int nthreads = threads_arg(threads);
        return run_batch(plants, policy, pushes, Q0, P0, steps, nthreads);
      }, py::arg("plants"), py::arg("x_ref"), py::arg("u_ref"), py::arg("gains"), py::arg("lower"), py::arg("upper"),
      py::arg("pushes"), py::arg("q0s"), py::arg("p0s"), py::arg("steps"), py::arg("threads") = py::none(), R"doc(
B closed-loop runs of `steps` steps in C++ (GIL released, `threads` threads): plants, a list of one or
B _core.Integrator (with or without contacts); the policy u^{k,a} = clamp(u_ref^{k,a} - K^k (x - x_ref^k))
from x_ref (S, nq + n), u_ref (S, (s+1) m), gains (S, m, 2n), lower, upper (m,); pushes: a list of one or
B lists of (step, body, point (3,) in the joint frame, world impulse (3,)[, world angular impulse (3,)]);
q0s (B, nq), p0s (B, n). Returns
(items: B rollout dicts with `controls` (K, (s+1) m), or None for an item that raised, errors (B,)).
)doc");
}

}  // namespace hovi::py_bind
