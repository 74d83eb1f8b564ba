// hovi.trajopt.solvers._ipopt: IPOPT's C++ interface on a hovi._core.trajopt.Program (ipopt_adapter.hpp),
// built when CMake finds IPOPT (the one way hovi solves with IPOPT). The solve runs with the GIL released; Python is called only by the program's
// extra terms and, after each iteration, by `callback` when one is given.
#include "../bindings/py_program.hpp"
#include "hovi/errors.hpp"
#include "ipopt_adapter.hpp"

#include <IpoptConfig.h>

namespace hovi::py_bind {

using namespace pybind11::literals;  // "name"_a = value: the keyword arguments of the result dicts

namespace {

IpoptOption option_of(const std::string& name, const py::handle& value) {
  IpoptOption o{name, IpoptOption::Text, "", 0, 0.0};
  if (py::isinstance<py::str>(value)) {
    o.text = value.cast<std::string>();
  } else if (py::isinstance<py::bool_>(value)) {
    throw py::type_error("IPOPT option '" + name + "': a boolean is not an IPOPT value");
  } else if (py::isinstance<py::int_>(value)) {
    o.kind = IpoptOption::Integer;
    o.integer = value.cast<int>();
  } else if (py::isinstance<py::float_>(value)) {
    o.kind = IpoptOption::Number;
    o.number = value.cast<double>();
  } else {
    throw py::type_error("IPOPT option '" + name + "': the value must be a str, int or float");
  }
  return o;
}

// Bounds: n real numbers, infinite ones allowed (no bound), NaN refused.
VecX bounds_vector(const py::handle& obj, const char* name, long n) {
  const RealArray a = real_array(obj, name);
  if (a.ndim() != 1 || a.shape(0) != n)
    throw InputError(std::string(name) + " must have shape (" + std::to_string(n) + ",)");
  VecX v = Eigen::Map<const VecX>(a.data(), n);
  if (v.hasNaN()) throw InputError(std::string(name) + " contains NaN");
  return v;
}

// The options of one IPOPT run: add_option checks each against IPOPT as it is added.
struct PyIpoptRun {
  std::vector<IpoptOption> options;
};

}  // namespace

void bind_ipopt(py::module_& m) {
  py::class_<PyIpoptRun>(m, "Ipopt", "IPOPT's options for solve(): add_option checks each with IPOPT.")
      .def(py::init<>())
      .def("add_option", [](PyIpoptRun& r, const std::string& name, const py::object& value) {
             IpoptOption o = option_of(name, value);
             if (!ipopt_accepts(o)) throw InputError("IPOPT refused the option '" + name + "'");
             r.options.push_back(std::move(o));
           }, py::arg("name"), py::arg("value"),
           "name: an IPOPT option; value: str, int or float (ValueError if IPOPT refuses the name or the value, "
           "TypeError for another type).")
      .def("solve", [](const PyIpoptRun& r, const PyProgram& p, const ArrayLike& x0, const ArrayLike& lower,
                       const ArrayLike& upper, const ArrayLike& cl, const ArrayLike& cu, bool exact_hessian,
                       py::object callback) {
             const NlpProgram& prog = *p.program;
             const long n = prog.n_variables(), mc = prog.n_constraints();
             if (exact_hessian && !p.hessian) throw InputError("exact_hessian needs Program.set_colouring first");
             IpoptProblemData d{bounds_vector(lower, "lower", n), bounds_vector(upper, "upper", n),
                                bounds_vector(cl, "cl", mc), bounds_vector(cu, "cu", mc), as_vector(x0, "x0", n)};
             // after each iteration: a pending signal (Ctrl-C) raised, then the callback if any
             IterationCallback cb = [callback](int it, double f, double pr, double du, double mu) {
               py::gil_scoped_acquire gil;
               if (PyErr_CheckSignals() != 0) throw py::error_already_set();
               return callback.is_none() || py::bool_(callback(it, f, pr, du, mu)).cast<bool>();
             };
             std::vector<IpoptOption> options = r.options;
             options.push_back({"hessian_approximation", IpoptOption::Text, exact_hessian ? "exact" : "limited-memory"});
             IpoptOutcome out;
             {
               py::gil_scoped_release release;
               out = solve_with_ipopt(prog, exact_hessian ? p.hessian.get() : nullptr, d, options, std::move(cb));
             }
             StrDict res("status"_a = out.status, "iterations"_a = out.iterations, "cost"_a = out.cost,
                         "x"_a = out.x, "lambda"_a = out.lambda, "z_lower"_a = out.z_lower,
                         "z_upper"_a = out.z_upper, "seconds"_a = out.seconds,
                         "callback_seconds"_a = out.callback_seconds, "hessian_seconds"_a = out.hessian_seconds,
                         "cpp_seconds"_a = prog.cpp_seconds(), "python_seconds"_a = prog.python_seconds());
             return res;
           }, py::arg("program"), py::arg("x0"), py::arg("lower"), py::arg("upper"), py::arg("cl"), py::arg("cu"),
           py::arg("exact_hessian") = false, py::arg("callback") = py::none(),
           "Solve `program` from x0 (n,) within lower <= x <= upper, cl <= g(x) <= cu, with the program's coloured "
           "Hessian (exact_hessian) or IPOPT's limited-memory one; callback(iteration, cost, inf_pr, inf_du, mu) -> "
           "bool after each iteration (False stops). Returns a dict: status (IPOPT's return "
           "code), iterations, cost, x, lambda, z_lower, z_upper and the timings in seconds.");
}

}  // namespace hovi::py_bind

PYBIND11_MODULE(_ipopt, m) {
  m.doc() = "IPOPT's C++ interface on hovi._core.trajopt.Program";
  m.attr("ipopt_version") = IPOPT_VERSION;  // the IPOPT hovi was built against
  pybind11::module_::import("hovi._core");  // Program and the exceptions' translators
  hovi::py_bind::bind_ipopt(m);
}
