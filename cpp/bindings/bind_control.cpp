// Bindings of the control layer (hovi._core.control): Riccati equations, the velocity state map and
// closed-loop runs in C++. The Pythonic layer is python/hovi/control/.
#include <chrono>
#include <string>
#include <vector>

#include "hovi/control/closed_loop.hpp"
#include "hovi/control/riccati.hpp"
#include "hovi/control/state_map.hpp"
#include "hovi/errors.hpp"
#include "py_contact.hpp"

namespace hovi::py_bind {
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

py::array_t<double> stacked(const std::vector<MatX>& mats) {
  const long K = long(mats.size()), r = K ? mats[0].rows() : 0, c = K ? mats[0].cols() : 0;
  py::array_t<double> out({K, r, c});
  auto w = out.mutable_unchecked<3>();
  for (long k = 0; k < K; ++k)
    for (long i = 0; i < r; ++i)
      for (long j = 0; j < c; ++j) w(k, i, j) = mats[k](i, j);
  return out;
}

// pushes: per run, a list of (step, body, point (3,), impulse (3,))
std::vector<std::vector<Push>> pushes_arg(const py::list& runs) {
  std::vector<std::vector<Push>> out;
  for (const py::handle& run : runs) {
    std::vector<Push> items;
    for (const py::handle& p : run.cast<py::list>()) {
      const py::tuple t = p.cast<py::tuple>();
      if (t.size() != 4) throw InputError("a push is (step, body, point (3,), impulse (3,))");
      items.push_back({t[0].cast<int>(), t[1].cast<int>(), as_vector(t[2], "push point", 3), as_vector(t[3], "push impulse", 3)});
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

template <class PyPlant, class Plant, class Result>
py::tuple run_batch(const py::list& plants, const Policy& policy, const py::list& pushes, const MatX& Q0, const MatX& P0,
                    int steps, int threads, const Plant& (*core)(const PyPlant&)) {
  std::vector<const Plant*> ps;
  for (const py::handle& h : plants) ps.push_back(&core(h.cast<const PyPlant&>()));
  const auto push = pushes_arg(pushes);
  std::vector<Result> out;
  std::vector<std::string> errors;
  std::vector<double> seconds(Q0.rows());
  {
    py::gil_scoped_release release;
    const auto t0 = std::chrono::steady_clock::now();
    errors = closed_loop_batch<Plant, Result>(ps, policy, push, Q0, P0, steps, out, threads);
    seconds.assign(Q0.rows(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  py::list items;
  for (std::size_t b = 0; b < out.size(); ++b)
    items.append(errors[b].empty() ? py::object(rollout_dict(out[b], seconds[b] / double(out.size()))) : py::none());
  return py::make_tuple(items, error_list(errors));
}

const GalerkinIntegrator& free_core(const PyIntegrator& p) { return p.integ(); }
const ContactIntegrator& contact_core(const PyContactIntegrator& p) { return p.core(); }

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
        return py::make_tuple(stacked(K), stacked(P));
      }, py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), py::arg("QN"), R"doc(
Finite-horizon LQR: A (N, n, n), B (N, n, m), Q (n, n) or (N, n, n), R (m, m) or (N, m, m), QN (n, n);
returns (K (N, m, n), P (N+1, n, n)), u^k = -K^k x^k, cost-to-go x^T P^k x.
)doc");
  m.def("velocity_state_map", [](const PyModel& model, const ArrayLike& q, const ArrayLike& p) {
        const MatX Q = as_matrix(q, "q", -1, model.model.n()), P = as_matrix(p, "p", Q.rows(), model.model.n());
        Data data(model.model);
        std::vector<MatX> out(Q.rows());
        for (long k = 0; k < Q.rows(); ++k) velocity_state_map(model.model, data, Q.row(k).transpose(), P.row(k).transpose(), out[k]);
        return stacked(out);
      }, py::arg("model"), py::arg("q"), py::arg("p"), R"doc(
T = d(q, q̇)/d(q, p) (K, 2n, 2n) at states q, p (K, n), q̇ = M(q)^{-1} p: a cost x_user^T W x_user on
(q, q̇) is x^T (T^T W T) x on the integrator's state x = (q, p).
)doc");
  m.def("closed_loop", [](const py::list& plants, const ArrayLike& x_ref, const ArrayLike& u_ref, const ArrayLike& gains,
                          const ArrayLike& lower, const ArrayLike& upper, const py::list& pushes, const ArrayLike& q0s,
                          const ArrayLike& p0s, int steps, const OptInt& threads) {
        if (plants.empty()) throw InputError("give at least one plant");
        const Policy policy = policy_arg(x_ref, u_ref, gains, lower, upper);
        const MatX Q0 = as_matrix(q0s, "q0s", -1, -1), P0 = as_matrix(p0s, "p0s", Q0.rows(), Q0.cols());
        if (steps < 0) throw InputError("steps must be non-negative");
        const int nthreads = threads_arg(threads);
        if (py::isinstance<PyIntegrator>(plants[0]))
          return run_batch<PyIntegrator, GalerkinIntegrator, Rollout>(plants, policy, pushes, Q0, P0, steps, nthreads, free_core);
        return run_batch<PyContactIntegrator, ContactIntegrator, ContactRollout>(plants, policy, pushes, Q0, P0, steps,
                                                                               nthreads, contact_core);
      }, py::arg("plants"), py::arg("x_ref"), py::arg("u_ref"), py::arg("gains"), py::arg("lower"), py::arg("upper"),
      py::arg("pushes"), py::arg("q0s"), py::arg("p0s"), py::arg("steps"), py::arg("threads") = py::none(), R"doc(
B closed-loop runs of `steps` steps in C++ (GIL released, `threads` threads): plants, a list of one or
B _core.Integrator or _core.ContactIntegrator; the policy u^{k,a} = clamp(u_ref^{k,a} - K^k (x - x_ref^k))
from x_ref (S, 2n), u_ref (S, (s+1) m), gains (S, m, 2n), lower, upper (m,); pushes: a list of one or
B lists of (step, body, point (3,) in the joint frame, world impulse (3,)); q0s, p0s (B, n). Returns
(items: B rollout dicts with `controls` (K, (s+1) m), or None for an item that raised, errors (B,)).
)doc");
}

}  // namespace hovi::py_bind
