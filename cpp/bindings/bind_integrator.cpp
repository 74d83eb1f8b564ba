// Bindings of the Galerkin integrator (hovi._core.Integrator), with or without contacts. The
// Pythonic layer (argument normalisation, Trajectory, exceptions) is python/hovi/integrator.py.
// Arrays of control points are (s+1, n) on the Python side (row a = q^{k,a}); controls (s+1, m).
#include <optional>
#include <chrono>

#include "hovi/errors.hpp"
#include "hovi/integrators/dense_direction.hpp"
#include "hovi/integrators/batch.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "hovi/quadrature/lobatto.hpp"
#include "py_integrator.hpp"

namespace hovi::py_bind {

using namespace pybind11::literals;  // "name"_a = value: the keyword arguments of the result dicts

namespace {

// A new array of the given shape filled with `fill` (NaN or -1: the slots of a batch that no
// item wrote).
template <class T>
py::array_t<T> filled(std::vector<py::ssize_t> shape, T fill) {
  py::array_t<T> a(shape);
  std::fill(a.mutable_data(), a.mutable_data() + a.size(), fill);
  return a;
}

// Rows 0..rows-1 of M into a[b, :rows, :] of a (B, R, C) array.
template <class T, class M>
void put_rows(py::array_t<T>& a, int b, const M& m, Eigen::Index rows) {
  auto r = a.template mutable_unchecked<3>();
  for (Eigen::Index k = 0; k < rows; ++k)
    for (Eigen::Index j = 0; j < m.cols(); ++j) r(b, k, j) = m(k, j);
}

// f(b) for each item b of a batch that finished; `status` gets "error" for those that raised.
template <class F>
void each_finished(const std::vector<std::string>& errors, py::list& status, F f) {
  for (int b = 0; b < static_cast<int>(errors.size()); ++b) {
    if (errors[b].empty()) f(b);
    else status.append("error");
  }
}

// The states of a batch: (B, nq) q, (B, n) p or q̇.
MatX batch_states(const PyIntegrator& p, const py::handle& x, const char* name, long rows, bool configuration) {
  return as_matrix(x, name, rows, configuration ? p.nq() : p.n());
}

// A step's guess of its impulses (C (2 + d),) or none (empty: none active).
VecX impulses_arg(const PyIntegrator& p, const py::handle& impulses) {
  if (impulses.is_none()) return VecX();
  if (!p.nz()) throw InputError("impulses are for an integrator with contacts");
  return as_vector(impulses, "impulses", p.nz());
}

}  // namespace

void bind_integrator(py::module_& m) {
  m.def("lagrange_basis", [](int s, const ArrayLike& x, bool derivative) {
        const Quadrature quad(s);
        const VecX xs = as_vector(x, "x", -1);
        MatX L(xs.size(), s + 1);
        for (Eigen::Index k = 0; k < xs.size(); ++k)
          L.row(k) = (derivative ? quad.basis_derivative(xs[k]) : quad.basis(xs[k])).transpose();
        return L;
      }, py::arg("s"), py::arg("x"), py::arg("derivative") = false,
      "x: (K,) points (on [0, 1] or beyond); returns (K, s+1): l_b(x_k), the Lagrange polynomials through the "
      "s+1 Lobatto nodes (Integrator.nodes), or their derivatives l_b'(x_k).");
  py::class_<PyIntegrator>(m, "Integrator", R"doc(
The core of hovi.Integrator (use that: it normalises arguments and returns Trajectory and
StepInfo objects). Arrays: q, p (n,); control points (s+1, n), row a = q^{k,a}; controls u (m,)
held over the step or (s+1, m) per control point; multipliers (s, n_constraints).
)doc")
      .def(py::init([](std::shared_ptr<PyModel> model, int s, double dt, double tol, double step_tol, int max_iterations,
                       int max_backtracks, bool line_search, const std::string& direction, bool reuse_jacobian,
                       double reuse_contraction, const std::string& predictor,
                       const std::optional<ContactModel>& contacts, double contact_tol, bool locate_impacts) {
             SolverOptions opt;
             if (predictor == "history") opt.predictor = Predictor::History;
             else if (predictor == "flow") opt.predictor = Predictor::Flow;
             else if (predictor == "auto") opt.predictor = Predictor::Auto;
             else throw InputError("predictor must be 'auto', 'history' or 'flow', got '" + predictor + "'");
             opt.reuse = reuse_jacobian ? Reuse::WithinStep : Reuse::Never;
             opt.reuse_contraction = reuse_contraction;
             if (direction == "dense") opt.direction = Direction::Dense;
             else if (direction == "recursive") opt.direction = Direction::Recursive;
             else if (direction == "auto") opt.direction = Direction::Auto;
             else throw InputError("direction must be 'auto', 'recursive' or 'dense', got '" + direction + "'");
             opt.tol = tol;
             opt.step_tol = step_tol;
             opt.max_iterations = max_iterations;
             opt.max_backtracks = max_backtracks;
             opt.line_search = line_search;
             return new PyIntegrator(model, s, dt, opt, contacts ? *contacts : ContactModel(),
                                     ContactOptions{contact_tol, locate_impacts});
           }),
           py::arg("model"), py::arg("s"), py::arg("dt"), py::arg("tol"), py::arg("step_tol"), py::arg("max_iterations"),
           py::arg("max_backtracks"), py::arg("line_search"), py::arg("direction"), py::arg("reuse_jacobian"),
           py::arg("reuse_contraction"), py::arg("predictor"), py::arg("contacts") = py::none(),
           py::arg("contact_tol") = 1e-10, py::arg("locate_impacts") = false,
           "A Galerkin integrator of order 2s with step dt on a copy of `model` (options as hovi.Integrator's); with "
           "`contacts` (a ContactModel) its steps have the contact stages (galerkin_integrator.hpp).")
      .def_property_readonly("n_contacts", [](const PyIntegrator& p) { return p.integ().contacts().size(); },
                             "The number of contact points C (0 without contacts).")
      .def_property_readonly("per_contact", [](const PyIntegrator& p) { return p.integ().contacts().per_contact(); },
                             "The unknowns per contact, 2 + d (with contacts).")
      .def_property_readonly("s", &PyIntegrator::s, "Number of Lobatto intervals; s+1 control points.")
      .def_property_readonly("direction_path", [](const PyIntegrator& p) {
            const auto& g = p.integ();
            return uses_dense_direction(g.options.direction, g.model(), g.quadrature().s) ? "dense" : "recursive";
          }, "The Newton direction computed: 'dense' or 'recursive'.")
      .def_property_readonly("n", &PyIntegrator::n, "Number of joints n of the model (the velocity's size, nv).")
      .def_property_readonly("nq", &PyIntegrator::nq, "The configuration's size: n, or n + 1 with a free base.")
      .def_property_readonly("n_controls", &PyIntegrator::m, "Number of control inputs m of the model.")
      .def("rollout_controls", [](const PyIntegrator& p, const OptArrayLike& u, long steps, std::optional<long> batch) {
            return p.rollout_controls(u, steps, batch ? *batch : -1);
          }, py::arg("u"), py::arg("steps"), py::arg("batch") = py::none(),
          R"(The controls of `steps` steps as rollout and rollout_batch take them: u of shape lead + (m,)
(held throughout), lead + (steps, m) (held per step) or lead + (steps, s+1, m) (per control point),
lead = () or (batch,), as an array lead + (steps, (s+1) m); None for None. Raises ValueError for a
model without controls, another shape, NaN or infinity.)")
      .def("step_controls", [](const PyIntegrator& p, const OptArrayLike& u, long count) {
            return p.step_controls(u, count);
          }, py::arg("u"), py::arg("count"),
          R"(The controls of one step from each of `count` states as step_batch takes them: u of shape
(count, m) (held) or (count, s+1, m) (per control point) as an array (count, (s+1) m); None for
None. Raises ValueError as rollout_controls.)")
      .def_property_readonly("n_constraints", &PyIntegrator::mc, "Number of constraint equations m_c of the model.")
      .def("project", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& qd, double tol) {
            auto qv = p.integ().project(as_vector(q, "q", p.n()), as_vector(qd, "qdot", p.n()), tol);
            return py::make_tuple(qv.first, qv.second);
          }, py::arg("q"), py::arg("qdot"), py::arg("tol") = 1e-12,
          "q, qdot: (n,); returns (q, qdot), each (n,), projected onto h(q) = 0 and Dh(q) q̇ = 0.")
      .def("constrained_residual", [](PyIntegrator& p, const ArrayLike& qc, const ArrayLike& lam,
                                      const ArrayLike& mom, const OptArrayLike& u) {
            MatX r, H;
            VecX p_next(p.n());
            p.integ().constrained_residual(p.control_points(qc, "control_points"), p.multipliers_arg(lam),
                                           as_vector(mom, "p", p.n()), p.controls(u), r, H, p_next);
            return py::make_tuple(MatX(r.transpose()), MatX(H.transpose()), p_next);
          }, py::arg("control_points"), py::arg("multipliers"), py::arg("p"), py::arg("u") = py::none(),
          "control_points (s+1, n), multipliers (s, m_c), p (n,); returns (r (s, n), h (s, m_c), p_next (n,)).")
      .def("constrained_direction", [](PyIntegrator& p, const ArrayLike& qc, const ArrayLike& lam,
                                       const ArrayLike& mom, const OptArrayLike& u) {
            MatX dz, dl;
            if (!p.integ().constrained_direction(p.control_points(qc, "control_points"), p.multipliers_arg(lam),
                                                 as_vector(mom, "p", p.n()), p.controls(u), dz, dl))
              throw InputError("the constrained DEL Jacobian (or its Schur complement) is singular here");
            return py::make_tuple(MatX(dz.transpose()), MatX(dl.transpose()));
          }, py::arg("control_points"), py::arg("multipliers"), py::arg("p"), py::arg("u") = py::none(),
          "control_points (s+1, n), multipliers (s, m_c), p (n,); returns the Newton direction (dq (s, n), dλ (s, m_c)).")
      .def_property_readonly("dt", &PyIntegrator::dt, "The time step (s).")
      .def_property_readonly("nodes", [](const PyIntegrator& p) { return VecX(p.quad().c); }, "(s+1,) Lobatto nodes c^a on [0, 1].")
      .def_property_readonly("weights", [](const PyIntegrator& p) { return VecX(p.quad().w); }, "(s+1,) Lobatto weights w^a.")
      .def_property_readonly("differentiation_matrix", [](const PyIntegrator& p) { return MatX(p.quad().b); },
                             "(s+1, s+1) b^{ab} = l_b'(c^a): q̇^a = (1/dt) sum_b b^{ab} q^b.")
      .def("momentum", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& qd) {
            return p.integ().momentum(as_vector(q, "q", p.nq()), as_vector(qd, "qdot", p.n()));
          }, py::arg("q"), py::arg("qdot"), "q (nq,), qdot (n,); returns p = M(q) q̇, (n,).")
      .def("velocity", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& mom) {
            return p.integ().velocity(as_vector(q, "q", p.nq()), as_vector(mom, "p", p.n()));
          }, py::arg("q"), py::arg("p"), "q (nq,), p (n,); returns the velocity q̇ (n,) of momentum p (see hovi.Integrator.velocity).")
      .def("energy", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& mom) {
            return p.integ().energy(as_vector(q, "q", p.nq()), as_vector(mom, "p", p.n()));
          }, py::arg("q"), py::arg("p"), "q (nq,), p (n,); returns K + V at (q, velocity(q, p)), a float.")
      .def("energies", [](PyIntegrator& p, const ArrayLike& Q, const ArrayLike& P) {
            const MatX q = as_matrix(Q, "q", -1, p.nq()), mom = as_matrix(P, "p", q.rows(), p.n());
            const GalerkinIntegrator& integ = p.integ();
            VecX E(q.rows());
            py::gil_scoped_release release;
            for (int k = 0; k < q.rows(); ++k) E[k] = integ.energy(q.row(k).transpose(), mom.row(k).transpose());
            return E;
          }, py::arg("q"), py::arg("p"), "q (K, nq), p (K, n); returns (K,) energy of every row, in C++ (GIL released).")
      .def("del_residual", [](PyIntegrator& p, const ArrayLike& qc, const ArrayLike& mom, const OptArrayLike& u) {
            MatX r(p.n(), p.s());
            VecX p_next(p.n());
            p.integ().residual(p.control_points(qc, "control_points"), as_vector(mom, "p", p.n()), p.controls(u), r, p_next);
            return py::make_tuple(MatX(r.transpose()), p_next);
          }, py::arg("control_points"), py::arg("p"), py::arg("u") = py::none(),
          "Algorithm 1. control_points (s+1, n), p (n,); returns (r (s, n), p_next (n,)).")
      .def("newton_direction", [](PyIntegrator& p, const ArrayLike& qc, const ArrayLike& mom, const OptArrayLike& u) {
            MatX dq(p.n(), p.s());
            if (!p.integ().direction(p.control_points(qc, "control_points"), as_vector(mom, "p", p.n()), p.controls(u), dq))
              throw InputError("the DEL Jacobian is singular at these control points (a pivot block is not invertible)");
            return MatX(dq.transpose());
          }, py::arg("control_points"), py::arg("p"), py::arg("u") = py::none(),
          "control_points (s+1, n), p (n,); returns the Newton direction dq (s, n) with J dq = -r.")
      .def("step", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& mom, const OptArrayLike& u,
                      const OptArrayLike& guess, const OptArrayLike& multipliers, const OptArrayLike& impulses) {
            const GalerkinIntegrator& integ = p.integ();
            const VecX q_in = as_vector(q, "q", p.nq());
            VecX qk = q_in.head(p.n()), pk = as_vector(mom, "p", p.n());
            const MatX uk = p.controls(u);
            if (integ.has_contacts() && !(guess.is_none() && multipliers.is_none()))
              throw InputError("guess and multipliers are not taken with contacts (the contact step makes its own guesses)");
            StepHistory h;
            const bool free = integ.model().rotation_chart >= 0;
            if (free) {  // the chart about q's attitude (θ = 0), the momentum in it
              if (!guess.is_none()) throw InputError("guess is not taken for a model with a free base");
              const FreeBase base(integ.model());
              base.state_to_chart(q_in, qk, h.centre, pk);
            }
            MatX qc(p.n(), p.s() + 1);
            if (!guess.is_none()) qc = p.control_points(guess, "guess");
            qc.col(0) = qk;
            h.lambda = multipliers.is_none() ? MatX::Zero(p.mc(), p.s()) : p.multipliers_arg(multipliers);
            h.z = impulses_arg(p, impulses);
            VecX p_next(p.n());
            ContactReport report;
            SolveInfo info;
            {
              py::gil_scoped_release release;
              info = guess.is_none() ? integ.step(pk, uk, qc, p_next, h, &report) : integ.solve(pk, uk, qc, p_next, &h.lambda);
            }
            StrDict d = info_dict(info);
            d["multipliers"] = MatX(h.lambda.transpose());
            if (free) {  // the end state public
              const FreeBase base(integ.model());
              VecX q_next(p.nq());
              base.state_to_public(qc.col(p.s()), h.centre, q_next, p_next);
              d["q_next"] = q_next;
            }
            if (integ.has_contacts()) {
              d["impulses"] = h.z;
              d["gaps"] = report.phi;
              d["pivots"] = report.pivots;
              d["impact"] = report.impact;
            }
            return py::make_tuple(MatX(qc.transpose()), p_next, d);
          }, py::arg("q"), py::arg("p"), py::arg("u") = py::none(), py::arg("guess") = py::none(),
          py::arg("multipliers") = py::none(), py::arg("impulses") = py::none(), R"doc(
One step from q (nq,), p (n,) (GIL released): guess (s+1, n) for a single Newton solve of the DEL equations
(no contacts), else every stage with its fallbacks (hovi.Integrator.step); multipliers (s, m_c) and
impulses (C (2 + d),) the first guesses. A free base: the control points in the chart about q's
attitude and the end state q_next (nq,) in the dict. Returns (control points (s+1, n), p_next (n,), info dict with
status, converged, iterations, factorizations, residual_evaluations, residual, multipliers (s, m_c), and
with contacts impulses (C (2 + d),), gaps at the end (C,), pivots and impact).
)doc")
      .def("rollout", [](PyIntegrator& p, const ArrayLike& q0, const ArrayLike& p0, int steps, const OptArrayLike& u,
                         const OptArrayLike& previous, const OptArrayLike& multipliers, const OptArrayLike& impulses) {
            const GalerkinIntegrator& integ = p.integ();
            const VecX q = as_vector(q0, "q0", p.nq()), mom = as_vector(p0, "p0", p.n());
            MatX U(0, 0);
            if (!u.is_none()) U = as_matrix(u, "u", steps, (p.s() + 1) * p.m());
            else if (p.m() > 0) U = MatX::Zero(steps, (p.s() + 1) * p.m());
            StepHistory start;
            if (!previous.is_none()) start.previous = p.control_points(previous, "previous");
            if (!multipliers.is_none()) start.lambda = p.multipliers_arg(multipliers);
            start.z = impulses_arg(p, impulses);
            Rollout r;
            double seconds;
            {
              py::gil_scoped_release release;
              const auto t0 = std::chrono::steady_clock::now();
              r = integ.rollout(q, mom, steps, U, std::move(start));
              seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            }
            return rollout_dict(r, seconds);
          }, py::arg("q0"), py::arg("p0"), py::arg("steps"), py::arg("u") = py::none(), py::arg("previous") = py::none(),
          py::arg("multipliers") = py::none(), py::arg("impulses") = py::none(), R"doc(
`steps` steps from q0 (nq,), p0 (n,) in C++ (GIL released); u (steps, (s+1) m); what the step before left:
previous, its control points (s+1, n) (for the predictor), multipliers (s, m_c), impulses (C (2 + d),)
(default none active). Returns a dict: q, p (K+1, n), control_points (K, (s+1) n), iterations,
factorizations, residual, status (per attempted step), multipliers (K, s m_c), steps K, seconds (a
free base: q (K+1, nq), step k's control points in the chart about q^k's attitude), and
with contacts pivots, impulses (K, C (2 + d)), gaps (K, C), impact (K,) and step_p (K+1, n).
)doc")
      .def("rollout_batch", [](PyIntegrator& p, const ArrayLike& q0, const ArrayLike& second, bool velocities, int steps,
                               const OptArrayLike& u, const OptInt& threads) {
            const GalerkinIntegrator& integ = p.integ();
            const int n = p.n(), s = p.s(), S1 = s + 1, m = p.m(), mc = p.mc();
            const MatX Q = batch_states(p, q0, "q0s", -1, true);
            const MatX V = batch_states(p, second, velocities ? "qdot0s" : "p0s", Q.rows(), false);
            if (steps < 0) throw InputError("steps must be non-negative");
            const long B = Q.rows();
            MatX U(0, 0);
            if (!u.is_none()) U = as_matrix(u, "u (B steps, (s+1) m)", B * steps, S1 * m);
            else if (m > 0) U = MatX::Zero(B * steps, S1 * m);
            const int nthreads = threads_arg(threads);
            RolloutBatch r;
            {
              py::gil_scoped_release release;
              r = rollout_batch(integ, {Q, V, velocities}, steps, U, nthreads);
            }
            const double nan = std::numeric_limits<double>::quiet_NaN();
            auto q = filled<double>({B, steps + 1, p.nq()}, nan), mom = filled<double>({B, steps + 1, n}, nan);
            auto cp = filled<double>({B, steps, S1 * n}, nan), lam = filled<double>({B, steps, s * mc}, nan);
            MatX res = MatX::Constant(B, steps, nan), impact = res;
            Eigen::MatrixXi its = Eigen::MatrixXi::Constant(B, steps, -1), facs = its, piv = its;
            const int nz = p.nz(), C = integ.contacts().size();
            auto z = filled<double>({B, steps, nz}, nan), gaps = filled<double>({B, steps, C}, nan);
            Eigen::VectorXi done = Eigen::VectorXi::Zero(B);
            py::list status;
            each_finished(r.errors, status, [&](int b) {
              const Rollout& ro = r.items[b];
              const int attempted = static_cast<int>(ro.status.size());
              put_rows(q, b, ro.q, ro.steps + 1);
              put_rows(mom, b, ro.p, ro.steps + 1);
              put_rows(cp, b, ro.control_points, ro.steps);
              put_rows(lam, b, ro.multipliers, ro.steps);
              res.row(b).head(attempted) = ro.residual.head(attempted).transpose();
              its.row(b).head(attempted) = ro.iterations.head(attempted).transpose();
              facs.row(b).head(attempted) = ro.factorizations.head(attempted).transpose();
              if (nz) {
                put_rows(z, b, ro.contact.impulses, ro.steps);
                put_rows(gaps, b, ro.contact.gaps, ro.steps);
                piv.row(b).head(attempted) = ro.contact.pivots.head(attempted).transpose();
                impact.row(b).head(ro.steps) = ro.contact.impact.head(ro.steps).transpose();
              }
              done[b] = ro.steps;
              status.append(attempted > ro.steps ? to_string(ro.status.back()) : std::string("converged"));
            });
            StrDict d("q"_a = q, "p"_a = mom, "control_points"_a = cp, "multipliers"_a = lam, "residual"_a = res,
                      "iterations"_a = its, "factorizations"_a = facs, "steps"_a = done, "status"_a = status,
                      "seconds"_a = VecX(Eigen::Map<const VecX>(r.seconds.data(), B)),
                      "errors"_a = error_list(r.errors));
            if (nz) {
              d["impulses"] = z;
              d["gaps"] = gaps;
              d["pivots"] = piv;
              d["impact"] = impact;
            }
            return d;
          }, py::arg("q0s"), py::arg("second"), py::arg("velocities"), py::arg("steps"), py::arg("u") = py::none(),
          py::arg("threads") = py::none(), R"doc(
`steps` steps from each of B initial states, q0s (B, nq) with second (B, n) the momenta p0 or, if
velocities, the velocities q̇0 (p0 = M(q0) q̇0 per state); u (B steps, (s+1) m), state b's controls
in rows b steps .. (b+1) steps - 1. In C++ on `threads` threads (None: HOVI_NUM_THREADS or every
core), GIL released; each state exactly as rollout. Returns a dict: q (B, steps+1, nq), p (B, steps+1, n) and
control_points (B, steps, (s+1) n), multipliers (B, steps, s m_c), residual (B, steps) (NaN
where not reached), iterations, factorizations (B, steps) (-1 where not attempted), steps (B,)
completed, status (B,) ('converged', the failed step's status, or 'error'), seconds (B,) and
errors (B,) (an exception's message, or None); with contacts impulses (B, steps, C (2 + d)), gaps (B,
steps, C), impact (B, steps) (NaN where not reached) and pivots (B, steps) (-1 where not attempted).
)doc")
      .def("step_batch", [](PyIntegrator& p, const ArrayLike& q, const ArrayLike& second, bool velocities,
                            const OptArrayLike& u, const OptInt& threads) {
            const GalerkinIntegrator& integ = p.integ();
            const int n = p.n(), s = p.s(), S1 = s + 1, m = p.m(), mc = p.mc();
            const MatX Q = batch_states(p, q, "qs", -1, true);
            const MatX V = batch_states(p, second, velocities ? "qdots" : "ps", Q.rows(), false);
            const long B = Q.rows();
            const MatX U = u.is_none() ? MatX::Zero(B, S1 * m) : as_matrix(u, "u (B, (s+1) m)", B, S1 * m);
            const int nthreads = threads_arg(threads);
            StepBatch r;
            {
              py::gil_scoped_release release;
              r = step_batch(integ, {Q, V, velocities}, U, nthreads);
            }
            const double nan = std::numeric_limits<double>::quiet_NaN();
            auto cp = filled<double>({B, S1, n}, nan), lam = filled<double>({B, s, mc}, nan);
            MatX p_next = MatX::Constant(B, n, nan), q_next = MatX::Constant(B, p.nq(), nan);
            VecX res = VecX::Constant(B, nan), seconds = VecX::Zero(B);
            Eigen::VectorXi its = Eigen::VectorXi::Constant(B, -1), facs = its, evals = its, piv = its;
            const int nz = p.nz(), C = integ.contacts().size();
            MatX z = MatX::Constant(B, nz, nan), gaps = MatX::Constant(B, C, nan);
            Eigen::Matrix<bool, Eigen::Dynamic, 1> converged = Eigen::Matrix<bool, Eigen::Dynamic, 1>::Zero(B);
            py::list status;
            each_finished(r.errors, status, [&](int b) {
              const StepBatchItem& it = r.items[b];
              put_rows(cp, b, MatX(it.qc.transpose()), S1);
              put_rows(lam, b, MatX(it.lambda.transpose()), s);
              p_next.row(b) = it.p_next.transpose();
              q_next.row(b) = it.q_next.transpose();
              res[b] = it.info.residual;
              its[b] = it.info.iterations;
              facs[b] = it.info.factorizations;
              evals[b] = it.info.residual_evaluations;
              converged[b] = it.info.converged();
              if (nz) {
                z.row(b) = it.z.transpose();
                gaps.row(b) = it.contact.phi.transpose();
                piv[b] = it.contact.pivots;
              }
              status.append(to_string(it.info.status));
              seconds[b] = it.seconds;
            });
            StrDict d("control_points"_a = cp, "multipliers"_a = lam, "q_next"_a = q_next, "p_next"_a = p_next,
                      "residual"_a = res,
                      "iterations"_a = its, "factorizations"_a = facs, "residual_evaluations"_a = evals,
                      "converged"_a = converged, "status"_a = status, "seconds"_a = seconds,
                      "errors"_a = error_list(r.errors));
            if (nz) {
              d["impulses"] = z;
              d["gaps"] = gaps;
              d["pivots"] = piv;
            }
            return d;
          }, py::arg("qs"), py::arg("second"), py::arg("velocities"), py::arg("u") = py::none(),
          py::arg("threads") = py::none(), R"doc(
One step (the fallbacks of step without a guess) from each of B states, qs (B, nq) with second
(B, n) the momenta p or, if velocities, the velocities q̇; u (B, (s+1) m), row b = state b's
controls per control point. In C++ on `threads` threads (None: HOVI_NUM_THREADS or every core),
GIL released; each state exactly as step. Returns a dict: control_points (B, s+1, n) (the last
iterate where a solve failed; a free base: in the chart about q's attitude), q_next (B, nq), p_next
(B, n), multipliers (B, s, m_c), residual (B,), iterations,
factorizations, residual_evaluations (B,), converged (B,), status (B,) (or 'error'), seconds (B,)
and errors (B,) (an exception's message, or None); with contacts impulses (B, C (2 + d)), gaps (B, C)
and pivots (B,).
)doc");
}

}  // namespace hovi::py_bind
