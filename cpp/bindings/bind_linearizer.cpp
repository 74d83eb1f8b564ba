// Bindings of the linearisation (hovi._core.Linearizer); the Pythonic layer is
// python/hovi/linearizer.py.
#include "hovi/integrators/batch.hpp"
#include "hovi/integrators/linearizer.hpp"
#include "py_integrator.hpp"

namespace hovi::py_bind {

namespace {
// The Linearizer of an integrator (safe for concurrent calls); lin() raises, as the integrator's
// calls do, once the model the integrator copied has changed.
struct PyLinearizer {
  explicit PyLinearizer(PyIntegrator& integ) : integ(integ), lin_(integ.integ()) {}
  PyIntegrator& integ;
  const Linearizer& lin() const {
    integ.integ();
    return lin_;
  }

 private:
  Linearizer lin_;
};
// The steps' other unknowns (Linearizer::trajectory_jacobians' W) of K steps: the multipliers
// (K, s m_c) of a constrained model, the impulses (K, C (2 + d)) with contacts, else none.
MatX step_unknowns(const PyIntegrator& p, const py::handle& multipliers, const py::handle& impulses, long K) {
  if (p.nz()) {
    if (impulses.is_none())
      throw InputError("an integrator with contacts needs the impulses of every step: give a trajectory it computed "
                       "(with its contact impulses)");
    return as_matrix(impulses, "impulses (steps, C (2 + d))", K, p.nz());
  }
  if (!impulses.is_none()) throw InputError("impulses are for an integrator with contacts");
  if (!p.mc()) return MatX();
  if (multipliers.is_none()) throw InputError("a constrained model needs the multipliers of every step");
  return as_matrix(multipliers, "multipliers (steps, s m_c)", K, p.s() * p.mc());
}
// The steps' public starts q^k (K x nq; K = 0: one step, a vector) of a free base, else none.
MatX starts_arg(const PyIntegrator& p, const py::handle& starts, long K) {
  const Model& model = p.integ().model();
  if (model.rotation_chart < 0) {
    if (!starts.is_none()) throw InputError("start is for a model with a free base");
    return MatX();
  }
  if (starts.is_none())
    throw InputError("a model with a free base needs each step's start q (its attitude places the step's chart)");
  if (K == 0) return as_vector(starts, "start", model.nq()).transpose();
  return as_matrix(starts, "starts (steps, nq)", K, model.nq());
}
}  // namespace

void bind_linearizer(py::module_& m) {
  py::class_<PyLinearizer>(m, "Linearizer", R"doc(
The core of hovi.Linearizer (use that): exact Jacobians of the DEL equations and of the step map
of an Integrator; arrays as for hovi._core.Integrator.
)doc")
      .def(py::init<PyIntegrator&>(), py::arg("integrator"), py::keep_alive<1, 2>(),
           "The linearisation of `integrator`'s DEL equations (the integrator is kept alive).")
      .def("del_jacobian", [](PyLinearizer& L, const ArrayLike& qc, const OptArrayLike& u, bool with_u,
                              const OptArrayLike& multipliers) -> Tuple<MatX, Optional<MatX>, Optional<MatX>> {
            const Linearizer& lin = L.lin();
            MatX Jq, Ju, Dh;
            const MatX q = L.integ.control_points(qc, "control_points"), uu = L.integ.controls(u);
            const bool constrained = !multipliers.is_none();
            if (constrained && L.integ.mc() == 0)
              throw InputError("multipliers were given but the model has no constraints");
            const MatX lam = constrained ? L.integ.multipliers_arg(multipliers) : MatX();
            {
              py::gil_scoped_release release;
              lin.del_jacobian(q, uu, Jq, (with_u || constrained) ? &Ju : nullptr, lam, constrained ? &Dh : nullptr);
            }
            return py::make_tuple(Jq, (with_u || constrained) ? py::cast(Ju) : py::none(),
                                  constrained ? py::cast(Dh) : py::none());
          }, py::arg("control_points"), py::arg("u") = py::none(), py::arg("with_u") = true,
          py::arg("multipliers") = py::none(), R"doc(
control_points (s+1, n), u (m,) or (s+1, m), multipliers (s, m_c) of a constrained model; returns
(dq ((s+1) n, (s+1) n), du ((s+1) n, (s+1) (m + m_c)) or None, dh (s m_c, (s+1) n) or None).
)doc")
      .def("step_jacobians", [](PyLinearizer& L, const ArrayLike& qc, const OptArrayLike& u, bool want_A, bool want_B,
                                const OptArrayLike& multipliers, const OptArrayLike& impulses, double smoothing,
                                const OptArrayLike& start) -> Tuple<Optional<MatX>, Optional<MatX>> {
            const Linearizer& lin = L.lin();
            const MatX q = L.integ.control_points(qc, "control_points"), uu = L.integ.controls(u);
            const int mc = L.integ.mc();
            if (mc && multipliers.is_none()) throw InputError("a constrained model needs the step's multipliers");
            MatX w;  // the step's multipliers (m_c x s), or its impulses (unknowns() x 1)
            if (L.integ.nz()) w = step_unknowns(L.integ, multipliers, impulses, 1).transpose();
            else if (mc) w = L.integ.multipliers_arg(multipliers);
            const MatX q0 = starts_arg(L.integ, start, 0);
            MatX A, B;
            bool ok;
            {
              py::gil_scoped_release release;
              ok = lin.step_jacobians(q, uu, want_A ? &A : nullptr, want_B ? &B : nullptr, w, nullptr, nullptr, smoothing,
                                      q0.size() ? VecX(q0.row(0).transpose()) : VecX());
            }
            if (!ok) throw InputError("the DEL Jacobian dR/dq^{k,1..s} is singular at these control points");
            return py::make_tuple(want_A ? py::cast(A) : py::none(), want_B ? py::cast(B) : py::none());
          }, py::arg("control_points"), py::arg("u") = py::none(), py::arg("want_A") = true, py::arg("want_B") = true,
          py::arg("multipliers") = py::none(), py::arg("impulses") = py::none(), py::arg("smoothing") = 0.0,
          py::arg("start") = py::none(), R"doc(
At a converged step's control points (s+1, n) (and multipliers (s, m_c), or with contacts its impulses
(1, C (2 + d)) and the smoothing; with a free base its start q^k (nq,)): returns (A (2n, 2n) or None,
B (2n, (s+1) m) or None), the Jacobians of (q^{k+1}, p^{k+1}) by (q^k, p^k) and u^{k,0..s} (a free
base: in tangent coordinates, (q ⊖ q_ref, p)).
)doc")
      .def("rollout_jacobians", [](PyLinearizer& L, const ArrayLike& cps, const OptArrayLike& u, bool want_A, bool want_B,
                                   const OptArrayLike& multipliers, const OptArrayLike& impulses, double smoothing,
                                   const OptArrayLike& starts)
                                   -> Tuple<Optional<py::array_t<double>>, Optional<py::array_t<double>>> {
            const Linearizer& lin = L.lin();
            const int n = L.integ.n(), S1 = L.integ.s() + 1, m = L.integ.m();
            const MatX C = as_matrix(cps, "control_points (steps, (s+1) n)", -1, S1 * n);
            const int N = static_cast<int>(C.rows());
            MatX U = MatX::Zero(N, S1 * m);
            if (!u.is_none()) U = as_matrix(u, "u (steps, (s+1) m)", N, S1 * m);
            const MatX W = step_unknowns(L.integ, multipliers, impulses, N);
            const MatX S = starts_arg(L.integ, starts, N);
            py::array_t<double> As(std::vector<py::ssize_t>{want_A ? N : 0, 2 * n, 2 * n});
            py::array_t<double> Bs(std::vector<py::ssize_t>{want_B ? N : 0, 2 * n, S1 * m});
            double* a = want_A ? As.mutable_data() : nullptr;
            double* b = want_B ? Bs.mutable_data() : nullptr;
            int failed;
            {
              py::gil_scoped_release release;
              failed = lin.trajectory_jacobians(C, U, W, a, b, smoothing, S);
            }
            if (failed >= 0)
              throw InputError("the step's Jacobian is singular at step " + std::to_string(failed) +
                               (L.integ.nz() ? " (redundant contacts held: the impulses do not determine the step's "
                                               "linearisation)" : ""));
            return py::make_tuple(want_A ? py::object(As) : py::none(), want_B ? py::object(Bs) : py::none());
          }, py::arg("control_points"), py::arg("u") = py::none(), py::arg("want_A") = true, py::arg("want_B") = true,
          py::arg("multipliers") = py::none(), py::arg("impulses") = py::none(), py::arg("smoothing") = 0.0,
          py::arg("starts") = py::none(), R"doc(
control_points (K, (s+1) n) of K converged steps, u (K, (s+1) m), multipliers (K, s m_c) of a
constrained model, or with contacts impulses (K, C (2 + d)) and smoothing (the central-path parameter,
in (N s)^2; 0 holds each contact's state), with a free base the steps' starts q^k (K, nq); returns (A (K, 2n, 2n) or None, B (K, 2n, (s+1) m) or
None), computed in C++ (GIL released).
)doc")
      .def("rollout_jacobians_batch", [](PyLinearizer& L, const ArrayLike& cps, int steps, const OptArrayLike& u,
                                         bool want_A, bool want_B, const OptArrayLike& multipliers,
                                         const OptArrayLike& impulses, double smoothing, const OptInt& threads,
                                         const OptArrayLike& starts)
                                         -> Tuple<Optional<py::array_t<double>>, Optional<py::array_t<double>>, py::list> {
            const Linearizer& lin = L.lin();
            const int n = L.integ.n(), S1 = L.integ.s() + 1, m = L.integ.m();
            if (steps < 1) throw InputError("steps must be at least 1");
            const MatX C = as_matrix(cps, "control_points (B steps, (s+1) n)", -1, S1 * n);
            if (C.rows() % steps) throw InputError("control_points must have B steps rows");
            const long B = C.rows() / steps;
            const MatX U = u.is_none() ? MatX::Zero(C.rows(), S1 * m) : as_matrix(u, "u (B steps, (s+1) m)", C.rows(), S1 * m);
            const MatX W = step_unknowns(L.integ, multipliers, impulses, C.rows());
            const MatX S = starts_arg(L.integ, starts, C.rows());
            const int nthreads = threads_arg(threads);
            py::array_t<double> As(std::vector<py::ssize_t>{want_A ? B : 0, steps, 2 * n, 2 * n});
            py::array_t<double> Bs(std::vector<py::ssize_t>{want_B ? B : 0, steps, 2 * n, S1 * m});
            double* a = want_A ? As.mutable_data() : nullptr;
            double* b = want_B ? Bs.mutable_data() : nullptr;
            std::vector<std::string> errors;
            {
              py::gil_scoped_release release;
              errors = trajectory_jacobians_batch(lin, static_cast<int>(B), steps, C, U, W, a, b, smoothing, nthreads, S);
            }
            return py::make_tuple(want_A ? py::object(As) : py::none(), want_B ? py::object(Bs) : py::none(),
                                  error_list(errors));
          }, py::arg("control_points"), py::arg("steps"), py::arg("u") = py::none(), py::arg("want_A") = true,
          py::arg("want_B") = true, py::arg("multipliers") = py::none(), py::arg("impulses") = py::none(),
          py::arg("smoothing") = 0.0, py::arg("threads") = py::none(), py::arg("starts") = py::none(), R"doc(
rollout_jacobians of B trajectories of `steps` converged steps each: control_points (B steps, (s+1) n),
u (B steps, (s+1) m), multipliers (B steps, s m_c) or impulses (B steps, C (2 + d)), starts (B steps, nq)
with a free base, trajectory b in
rows b steps .. (b+1) steps - 1; in C++ on `threads` threads (None: HOVI_NUM_THREADS or every core),
GIL released. Returns (A (B, steps, 2n, 2n) or None, B (B, steps, 2n, (s+1) m) or None, errors (B,):
None, or the message for a trajectory with a singular step, whose blocks are left unset).
)doc");
}

}  // namespace hovi::py_bind
