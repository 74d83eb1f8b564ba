// Bindings of the Galerkin integrator (hovi._core.Integrator). The Pythonic layer (argument
// normalisation, Trajectory, exceptions) is python/hovi/integrator.py. Arrays of control points
// are (s+1, n) on the Python side (row a = q^{k,a}); controls (s+1, m).
#include <chrono>

#include "hovi/errors.hpp"
#include "hovi/integrators/dense_direction.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "py_integrator.hpp"

namespace hovi::py_bind {

namespace {

py::dict info_dict(const SolveInfo& info) {
  py::dict d;
  d["status"] = to_string(info.status);
  d["converged"] = info.converged();
  d["iterations"] = info.iterations;
  d["factorizations"] = info.factorizations;
  d["residual_evaluations"] = info.residual_evaluations;
  d["residual"] = info.residual;
  return d;
}

}  // namespace

void bind_integrator(py::module_& m) {
  py::class_<PyIntegrator>(m, "Integrator")
      .def(py::init([](std::shared_ptr<PyModel> model, int s, double dt, double tol, double step_tol, int max_iterations,
                       int max_backtracks, bool line_search, const std::string& direction, bool reuse_jacobian,
                       double reuse_contraction) {
             SolverOptions opt;
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
             return new PyIntegrator(model, s, dt, opt);
           }),
           py::arg("model"), py::arg("s"), py::arg("dt"), py::arg("tol"), py::arg("step_tol"), py::arg("max_iterations"),
           py::arg("max_backtracks"), py::arg("line_search"), py::arg("direction"), py::arg("reuse_jacobian"),
           py::arg("reuse_contraction"))
      .def_property_readonly("s", &PyIntegrator::s)
      .def_property_readonly("direction_path", [](const PyIntegrator& p) {
            const auto& g = p.integ();
            return uses_dense_direction(g.options.direction, g.model(), g.quadrature().s) ? "dense" : "recursive";
          })
      .def_property_readonly("n", &PyIntegrator::n)
      .def_property_readonly("n_controls", &PyIntegrator::m)
      .def_property_readonly("n_constraints", &PyIntegrator::mc)
      .def("project", [](PyIntegrator& p, const py::object& q, const py::object& qd, double tol) {
            auto qv = p.integ().project(as_vector(q, "q", p.n()), as_vector(qd, "qdot", p.n()), tol);
            return py::make_tuple(qv.first, qv.second);
          }, py::arg("q"), py::arg("qdot"), py::arg("tol") = 1e-12)
      .def("constrained_residual", [](PyIntegrator& p, const py::object& qc, const py::object& lam,
                                      const py::object& mom, const py::object& u) {
            MatX r, H;
            VecX p_next(p.n());
            p.integ().constrained_residual(p.control_points(qc, "control_points"), p.multipliers_arg(lam),
                                           as_vector(mom, "p", p.n()), p.controls(u), r, H, p_next);
            return py::make_tuple(MatX(r.transpose()), MatX(H.transpose()), p_next);
          }, py::arg("control_points"), py::arg("multipliers"), py::arg("p"), py::arg("u") = py::none())
      .def("constrained_direction", [](PyIntegrator& p, const py::object& qc, const py::object& lam,
                                       const py::object& mom, const py::object& u) {
            MatX dz, dl;
            if (!p.integ().constrained_direction(p.control_points(qc, "control_points"), p.multipliers_arg(lam),
                                                 as_vector(mom, "p", p.n()), p.controls(u), dz, dl))
              throw InputError("the constrained DEL Jacobian (or its Schur complement) is singular here");
            return py::make_tuple(MatX(dz.transpose()), MatX(dl.transpose()));
          }, py::arg("control_points"), py::arg("multipliers"), py::arg("p"), py::arg("u") = py::none())
      .def_property_readonly("dt", &PyIntegrator::dt)
      .def_property_readonly("nodes", [](const PyIntegrator& p) { return VecX(p.quad().c); })
      .def_property_readonly("weights", [](const PyIntegrator& p) { return VecX(p.quad().w); })
      .def_property_readonly("differentiation_matrix", [](const PyIntegrator& p) { return MatX(p.quad().b); })
      .def("momentum", [](PyIntegrator& p, const py::object& q, const py::object& qd) {
            return p.integ().momentum(as_vector(q, "q", p.n()), as_vector(qd, "qdot", p.n()));
          }, py::arg("q"), py::arg("qdot"))
      .def("velocity", [](PyIntegrator& p, const py::object& q, const py::object& mom) {
            return p.integ().velocity(as_vector(q, "q", p.n()), as_vector(mom, "p", p.n()));
          }, py::arg("q"), py::arg("p"))
      .def("energy", [](PyIntegrator& p, const py::object& q, const py::object& mom) {
            return p.integ().energy(as_vector(q, "q", p.n()), as_vector(mom, "p", p.n()));
          }, py::arg("q"), py::arg("p"))
      .def("energies", [](PyIntegrator& p, const py::object& Q, const py::object& P) {
            const MatX q = as_matrix(Q, "q", -1, p.n()), mom = as_matrix(P, "p", q.rows(), p.n());
            const GalerkinIntegrator& integ = p.integ();
            VecX E(q.rows());
            py::gil_scoped_release release;
            for (int k = 0; k < q.rows(); ++k) E[k] = integ.energy(q.row(k).transpose(), mom.row(k).transpose());
            return E;
          }, py::arg("q"), py::arg("p"))
      .def("del_residual", [](PyIntegrator& p, const py::object& qc, const py::object& mom, const py::object& u) {
            MatX r(p.n(), p.s());
            VecX p_next(p.n());
            p.integ().residual(p.control_points(qc, "control_points"), as_vector(mom, "p", p.n()), p.controls(u), r, p_next);
            return py::make_tuple(MatX(r.transpose()), p_next);
          }, py::arg("control_points"), py::arg("p"), py::arg("u") = py::none())
      .def("newton_direction", [](PyIntegrator& p, const py::object& qc, const py::object& mom, const py::object& u) {
            MatX dq(p.n(), p.s());
            if (!p.integ().direction(p.control_points(qc, "control_points"), as_vector(mom, "p", p.n()), p.controls(u), dq))
              throw InputError("the DEL Jacobian is singular at these control points (a pivot block is not invertible)");
            return MatX(dq.transpose());
          }, py::arg("control_points"), py::arg("p"), py::arg("u") = py::none())
      .def("step", [](PyIntegrator& p, const py::object& q, const py::object& mom, const py::object& u,
                      const py::object& guess, const py::object& multipliers) {
            const GalerkinIntegrator& integ = p.integ();
            const VecX qk = as_vector(q, "q", p.n()), pk = as_vector(mom, "p", p.n());
            const MatX uk = p.controls(u);
            MatX qc(p.n(), p.s() + 1);
            if (!guess.is_none()) qc = p.control_points(guess, "guess");
            qc.col(0) = qk;
            MatX lambda = multipliers.is_none() ? MatX::Zero(p.mc(), p.s()) : p.multipliers_arg(multipliers);
            VecX p_next(p.n());
            SolveInfo info;
            {
              py::gil_scoped_release release;
              info = guess.is_none() ? integ.robust_step(pk, uk, MatX(), qc, p_next, &lambda)
                                     : integ.step(pk, uk, qc, p_next, &lambda);
            }
            py::dict d = info_dict(info);
            d["multipliers"] = MatX(lambda.transpose());
            return py::make_tuple(MatX(qc.transpose()), p_next, d);
          }, py::arg("q"), py::arg("p"), py::arg("u") = py::none(), py::arg("guess") = py::none(),
          py::arg("multipliers") = py::none())
      .def("rollout", [](PyIntegrator& p, const py::object& q0, const py::object& p0, int steps, const py::object& u,
                         const py::object& previous, const py::object& multipliers) {
            const GalerkinIntegrator& integ = p.integ();
            const VecX q = as_vector(q0, "q0", p.n()), mom = as_vector(p0, "p0", p.n());
            MatX U(0, 0), prev;
            if (!u.is_none()) U = as_matrix(u, "u", steps, (p.s() + 1) * p.m());
            else if (p.m() > 0) U = MatX::Zero(steps, (p.s() + 1) * p.m());
            if (!previous.is_none()) prev = p.control_points(previous, "previous");
            const MatX lambda0 = multipliers.is_none() ? MatX() : p.multipliers_arg(multipliers);
            Rollout r;
            double seconds;
            {
              py::gil_scoped_release release;
              const auto t0 = std::chrono::steady_clock::now();
              r = integ.rollout(q, mom, steps, U, prev, lambda0);
              seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            }
            py::dict d;
            d["q"] = MatX(r.q.topRows(r.steps + 1));
            d["p"] = MatX(r.p.topRows(r.steps + 1));
            d["control_points"] = MatX(r.control_points.topRows(r.steps));
            const int attempted = static_cast<int>(r.status.size());
            d["iterations"] = Eigen::VectorXi(r.iterations.head(attempted));
            d["factorizations"] = Eigen::VectorXi(r.factorizations.head(attempted));
            d["residual"] = VecX(r.residual.head(attempted));
            py::list st;
            for (SolveStatus x : r.status) st.append(to_string(x));
            d["status"] = st;
            d["multipliers"] = MatX(r.multipliers.topRows(r.steps));
            d["steps"] = r.steps;
            d["seconds"] = seconds;
            return d;
          }, py::arg("q0"), py::arg("p0"), py::arg("steps"), py::arg("u") = py::none(), py::arg("previous") = py::none(),
          py::arg("multipliers") = py::none());
}

}  // namespace hovi::py_bind
