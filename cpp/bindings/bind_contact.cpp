// Bindings of the contact simulator (hovi._core.ContactIntegrator). The Pythonic layer (the
// contacts as hovi.contact.Contacts, Trajectory, exceptions) is python/hovi/integrator.py.
#include <chrono>
#include <string>
#include <vector>

#include "hovi/contact/contact_integrator.hpp"
#include "hovi/contact/contact_linearizer.hpp"
#include "hovi/errors.hpp"
#include "hovi/parallel/parallel_for.hpp"
#include "py_contact.hpp"

namespace hovi::py_bind {

ContactModel contact_model(const std::vector<int>& bodies, const ArrayLike& points,
                           double ground, const ArrayLike& gaps, const ArrayLike& boxes, double mu,
                           const ArrayLike& directions) {
  ContactModel cm;
  const MatX P = as_matrix(points, "points", static_cast<long>(bodies.size()), 3);
  for (std::size_t i = 0; i < bodies.size(); ++i) cm.points.push_back({bodies[i], P.row(i).transpose()});
  cm.terrain.ground = ground;
  const RealArray g = real_array(gaps, "gaps");
  if (g.size()) {
    const MatX G = as_matrix(gaps, "gaps (x0, x1, depth)", -1, 3);
    for (Eigen::Index i = 0; i < G.rows(); ++i) cm.terrain.gaps.push_back({G(i, 0), G(i, 1), G(i, 2)});
  }
  const RealArray b = real_array(boxes, "boxes");
  if (b.size()) {  // y0, y1 may be infinite: read without as_matrix's finiteness check
    if (b.ndim() != 2 || b.shape(1) != 5) throw InputError("boxes must have shape (B, 5): x0, x1, top, y0, y1");
    auto r = b.unchecked<2>();
    for (py::ssize_t i = 0; i < b.shape(0); ++i) cm.terrain.boxes.push_back({r(i, 0), r(i, 1), r(i, 2), r(i, 3), r(i, 4)});
  }
  cm.mu = mu;
  cm.D = as_matrix(directions, "friction directions", -1, 3);
  return cm;
}

void bind_contact(py::module_& m) {
  py::class_<PyContactIntegrator>(m, "ContactIntegrator", R"doc(
The variational integrator of an Integrator (its model, s, dt and Newton options) with hard point
contacts and Coulomb friction (cpp/include/hovi/contact/contact_solver.hpp). hovi.Integrator(...,
contacts=...) makes and uses it; the arguments are hovi.contact.Contacts' (bodies, points in the
joint frames, the terrain's ground, gaps (G, 3) and boxes (B, 5), mu, friction directions (d, 3)).
)doc")
      .def(py::init([](const PyIntegrator& integrator, const std::vector<int>& bodies, const ArrayLike& points,
                       double ground, const ArrayLike& gaps, const ArrayLike& boxes, double mu,
                       const ArrayLike& directions, double contact_tol, bool locate_impacts) {
             ContactModel cm =
                 contact_model(bodies, points, ground, gaps, boxes, mu, directions);
             return std::make_unique<PyContactIntegrator>(integrator, std::move(cm), contact_tol, locate_impacts);
           }),
           py::keep_alive<1, 2>(),
           py::arg("integrator"), py::arg("bodies"), py::arg("points"), py::arg("ground"), py::arg("gaps"),
           py::arg("boxes"), py::arg("mu"), py::arg("directions"), py::arg("contact_tol") = 1e-10,
           py::arg("locate_impacts") = false, R"doc(
The contact simulator over `integrator` (a hovi._core.Integrator) with C contact points: bodies (C,)
indices, points (C, 3) in the bodies' joint frames; the terrain's ground height, gaps (G, 3) rows
(x0, x1, depth), boxes (B, 5) rows (x0, x1, top, y0, y1); friction mu; directions (d, 3) horizontal
unit vectors; contact_tol the complementarity tolerance (m and N s); locate_impacts: split a step
at an impact found on its polynomial (contact_integrator.hpp).
)doc")
      .def_property_readonly("n_contacts", [](const PyContactIntegrator& c) { return c.core().contacts().size(); },
                             "The number of contact points C.")
      .def_property_readonly("per_contact", [](const PyContactIntegrator& c) { return c.core().contacts().per_contact(); },
                             "The unknowns per contact, 2 + d: the normal impulse, d friction impulses, the sliding slack.")
      .def("step", [](const PyContactIntegrator& c, const ArrayLike& q, const ArrayLike& mom, const OptArrayLike& u,
                      const OptArrayLike& impulses) {
            const ContactIntegrator& core = c.core();
            const PyIntegrator& pi = c.py();
            const int n = pi.n(), s = pi.s(), nz = core.contacts().unknowns();
            const VecX qk = as_vector(q, "q", n), pk = as_vector(mom, "p", n);
            const MatX uk = pi.controls(u);
            VecX z = impulses.is_none() ? VecX::Zero(nz) : as_vector(impulses, "impulses", nz);
            MatX qc(n, s + 1);
            qc.col(0) = qk;
            VecX p_next(n), phi(core.contacts().size());
            int pivots = 0;
            double impact = 0;
            SolveInfo info;
            {
              py::gil_scoped_release release;
              info = core.step(pk, uk, MatX(), qc, p_next, z, phi, &pivots, &impact);
            }
            StrDict d = info_dict(info);
            d["pivots"] = pivots;
            d["impact"] = impact;
            return py::make_tuple(MatX(qc.transpose()), p_next, z, phi, d);
          }, py::arg("q"), py::arg("p"), py::arg("u") = py::none(), py::arg("impulses") = py::none(), R"doc(
One contact step from q, p (n,) (GIL released); impulses: the first guess (C (2 + d),), default none
active. Returns (control points (s+1, n), p_next (n,), impulses (C (2 + d),), gaps at the end (C,),
info dict).
)doc")
      .def("rollout", [](const PyContactIntegrator& c, const ArrayLike& q0, const ArrayLike& p0, int steps,
                         const OptArrayLike& u, const OptArrayLike& impulses) {
            const ContactIntegrator& core = c.core();
            const PyIntegrator& pi = c.py();
            const VecX q = as_vector(q0, "q0", pi.n()), mom = as_vector(p0, "p0", pi.n());
            MatX U(0, 0);
            if (!u.is_none()) U = as_matrix(u, "u", steps, (pi.s() + 1) * pi.m());
            else if (pi.m() > 0) U = MatX::Zero(steps, (pi.s() + 1) * pi.m());
            const VecX z0 = impulses.is_none() ? VecX() : as_vector(impulses, "impulses", core.contacts().unknowns());
            ContactRollout r;
            double seconds;
            {
              py::gil_scoped_release release;
              const auto t0 = std::chrono::steady_clock::now();
              r = core.rollout(q, mom, steps, U, z0);
              seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            }
            return rollout_dict(r, seconds);
          }, py::arg("q0"), py::arg("p0"), py::arg("steps"), py::arg("u") = py::none(),
          py::arg("impulses") = py::none(), R"doc(
`steps` contact steps from q0, p0 (n,) in C++ (GIL released); u (steps, (s+1) m); impulses: those of
the step before (C (2 + d),), default none active. Returns a dict:
q, p (K+1, n), control_points (K, (s+1) n), iterations, factorizations, residual, pivots, status
(per attempted step), impulses (K, C (2 + d)), gaps (K, C), steps K, seconds.
)doc")
      .def("rollout_jacobians", [](const PyContactIntegrator& c, const ArrayLike& cps, const OptArrayLike& u,
                                   const ArrayLike& impulses, bool want_A, bool want_B, double smoothing)
                                   -> Tuple<Optional<py::array_t<double>>, Optional<py::array_t<double>>> {
            const ContactLinearizer& lin = c.lin();
            const PyIntegrator& pi = c.py();
            const int n = pi.n(), S1 = pi.s() + 1, m = pi.m(), nz = c.core().contacts().unknowns();
            const MatX C = as_matrix(cps, "control_points (steps, (s+1) n)", -1, S1 * n);
            const int N = static_cast<int>(C.rows());
            const MatX U = u.is_none() ? MatX::Zero(N, S1 * m) : as_matrix(u, "u (steps, (s+1) m)", N, S1 * m);
            const MatX Z = as_matrix(impulses, "impulses (steps, C (2 + d))", N, nz);
            py::array_t<double> As(std::vector<py::ssize_t>{want_A ? N : 0, 2 * n, 2 * n});
            py::array_t<double> Bs(std::vector<py::ssize_t>{want_B ? N : 0, 2 * n, S1 * m});
            double* a = want_A ? As.mutable_data() : nullptr;
            double* b = want_B ? Bs.mutable_data() : nullptr;
            int failed;
            {
              py::gil_scoped_release release;
              failed = lin.trajectory_jacobians(C, U, Z, a, b, smoothing);
            }
            if (failed >= 0)
              throw InputError("the contact step's Jacobian is singular at step " + std::to_string(failed) +
                               " (redundant contacts held: the impulses do not determine the step's linearisation)");
            return py::make_tuple(want_A ? py::object(As) : py::none(), want_B ? py::object(Bs) : py::none());
          }, py::arg("control_points"), py::arg("u"), py::arg("impulses"), py::arg("want_A") = true,
          py::arg("want_B") = true, py::arg("smoothing") = 0.0, R"doc(
The step Jacobians of K converged contact steps (contact_linearizer.hpp): control_points (K, (s+1) n),
u (K, (s+1) m) or None, impulses (K, C (2 + d)); smoothing: the central-path parameter kappa ((N s)^2;
0: the contact state held); returns (A (K, 2n, 2n) or None, B (K, 2n, (s+1) m) or None), in C++
(GIL released).
)doc")
      .def("rollout_batch", [](const PyContactIntegrator& c, const ArrayLike& q0s, const ArrayLike& p0s, int steps,
                               const OptArrayLike& u, const OptInt& threads) {
            const ContactIntegrator& core = c.core();
            const PyIntegrator& pi = c.py();
            const int n = pi.n(), S1 = pi.s() + 1, m = pi.m();
            const MatX Q = as_matrix(q0s, "q0s", -1, n), P = as_matrix(p0s, "p0s", Q.rows(), n);
            if (steps < 0) throw InputError("steps must be non-negative");
            const long B = Q.rows();
            const MatX U = u.is_none() ? MatX::Zero(B * steps, S1 * m) : as_matrix(u, "u (B steps, (s+1) m)", B * steps, S1 * m);
            const int nthreads = thread_count(threads_arg(threads));
            std::vector<ContactRollout> items(B);
            std::vector<double> seconds(B, 0.0);
            std::vector<std::string> errors;
            {
              py::gil_scoped_release release;
              errors = parallel_for(static_cast<int>(B), nthreads, [&](int b, int) {
                const auto t0 = std::chrono::steady_clock::now();
                items[b] = core.rollout(Q.row(b).transpose(), P.row(b).transpose(), steps,
                                        m ? MatX(U.middleRows(static_cast<Eigen::Index>(b) * steps, steps)) : MatX(0, 0));
                seconds[b] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
              });
            }
            py::list out;
            for (long b = 0; b < B; ++b) out.append(errors[b].empty() ? py::object(rollout_dict(items[b], seconds[b])) : py::none());
            return py::make_tuple(out, error_list(errors));
          }, py::arg("q0s"), py::arg("p0s"), py::arg("steps"), py::arg("u") = py::none(), py::arg("threads") = py::none(),
          R"doc(
rollout from each of B states q0s, p0s (B, n) on `threads` C++ threads (GIL released); u (B steps,
(s+1) m). Returns (items: B rollout dicts, or None for an item that raised, errors (B,)).
)doc")
      .def("step_batch", [](const PyContactIntegrator& c, const ArrayLike& qs, const ArrayLike& ps,
                            const OptArrayLike& u, const OptInt& threads) {
            const ContactIntegrator& core = c.core();
            const PyIntegrator& pi = c.py();
            const int n = pi.n(), s = pi.s(), S1 = s + 1, m = pi.m(), nz = core.contacts().unknowns();
            const MatX Q = as_matrix(qs, "qs", -1, n), P = as_matrix(ps, "ps", Q.rows(), n);
            const long B = Q.rows();
            const MatX U = u.is_none() ? MatX::Zero(B, S1 * m) : as_matrix(u, "u (B, (s+1) m)", B, S1 * m);
            const int nthreads = thread_count(threads_arg(threads));
            std::vector<MatX> qcs(B, MatX(n, S1));
            MatX p_next(B, n), Z = MatX::Zero(B, nz), phi(B, core.contacts().size());
            std::vector<SolveInfo> infos(B);
            std::vector<int> pivots(B, 0);
            std::vector<double> seconds(B, 0.0);
            std::vector<std::string> errors;
            {
              py::gil_scoped_release release;
              errors = parallel_for(static_cast<int>(B), nthreads, [&](int b, int) {
                const auto t0 = std::chrono::steady_clock::now();
                qcs[b].col(0) = Q.row(b).transpose();
                VecX pn(n), z = VecX::Zero(nz), ph(core.contacts().size());
                MatX ub = Eigen::Map<const MatX>(U.row(b).eval().data(), m, S1);
                infos[b] = core.step(P.row(b).transpose(), ub, MatX(), qcs[b], pn, z, ph, &pivots[b]);
                p_next.row(b) = pn.transpose();
                Z.row(b) = z.transpose();
                phi.row(b) = ph.transpose();
                seconds[b] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
              });
            }
            py::list items;
            for (long b = 0; b < B; ++b) {
              if (!errors[b].empty()) {
                items.append(py::none());
                continue;
              }
              StrDict d = info_dict(infos[b]);
              d["pivots"] = pivots[b];
              d["control_points"] = MatX(qcs[b].transpose());
              d["p_next"] = VecX(p_next.row(b).transpose());
              d["impulses"] = VecX(Z.row(b).transpose());
              d["gaps"] = VecX(phi.row(b).transpose());
              d["seconds"] = seconds[b];
              items.append(d);
            }
            return py::make_tuple(items, error_list(errors));
          }, py::arg("qs"), py::arg("ps"), py::arg("u") = py::none(), py::arg("threads") = py::none(), R"doc(
One contact step from each of B states qs, ps (B, n) on `threads` C++ threads (GIL released); u (B,
(s+1) m). Returns (items: B dicts as step's info with control_points, p_next, impulses, gaps,
seconds, or None for an item that raised, errors (B,)).
)doc");
}

}  // namespace hovi::py_bind
