// Bindings of the trajectory-optimisation transcriptions (hovi._core.trajopt); the Problem, the
// costs and the solver are Python (python/hovi/trajopt/). Every evaluation is one C++ call over
// the whole trajectory, with the GIL released.
#include "hovi/errors.hpp"
#include "hovi/trajopt/hermite_simpson_transcription.hpp"
#include "hovi/trajopt/variational_transcription.hpp"
#include "py_transcription.hpp"

namespace hovi::py_bind {

namespace {

ControlMode parse_controls(const std::string& c) {
  if (c == "per_point") return ControlMode::PerPoint;
  if (c == "held") return ControlMode::Held;
  throw InputError("controls must be 'per_point' or 'held', got '" + c + "'");
}

// The methods every transcription shares: sizes, sparsity, constraint values and Jacobian values.
template <class T>
void bind_common(py::class_<PyTranscription<T>>& c) {
  using P = PyTranscription<T>;
  c.def_property_readonly("n_variables", [](const P& p) { return p.t.n_variables(); }, "Length of the variable vector x.")
      .def_property_readonly("n_constraints", [](const P& p) { return p.t.n_constraints(); }, "Length of g(x).")
      .def_property_readonly("nnz", [](const P& p) { return p.t.structure().nnz(); }, "Number of nonzeros of the Jacobian.")
      .def_property_readonly("structure", [](const P& p) {
            return py::make_tuple(p.t.structure().rows, p.t.structure().cols);
          }, "(rows (nnz,), cols (nnz,)) of the Jacobian's nonzeros, in the order `jacobian` returns values.")
      .def("constraints", [](const P& p, const ArrayLike& x) {
            const T& t = p.get();
            const VecX xv = as_vector(x, "x", t.n_variables());
            VecX g(t.n_constraints());
            py::gil_scoped_release release;
            t.constraints(xv, g);
            return g;
          }, py::arg("x"), "x: (n_variables,); returns g(x), (n_constraints,), the dynamics (and holonomic) constraints of the whole trajectory.")
      .def("jacobian", [](const P& p, const ArrayLike& x) {
            const T& t = p.get();
            const VecX xv = as_vector(x, "x", t.n_variables());
            VecX values(t.structure().nnz());
            py::gil_scoped_release release;
            t.jacobian(xv, values);
            return values;
          }, py::arg("x"), "x: (n_variables,); returns the Jacobian's values (nnz,) at x, in `structure` order.");
}

}  // namespace

void bind_trajopt(py::module_& m) {
  py::module_ t = m.def_submodule("trajopt", "Transcriptions of trajectory-optimisation problems");
  using PV = PyTranscription<VariationalTranscription>;
  py::class_<PV> vi(t, "VariationalTranscription", R"doc(
The Galerkin VI of order 2s as NLP constraints (variational_transcription.hpp): variables q at the
N s + 1 control points, p at the N + 1 knots, controls (per point or held per stage), multipliers
λ^{k,0..s-1}; rows: per stage the s DEL residuals and the momentum update, then h(q^j).
)doc");
  vi.def(py::init([](std::shared_ptr<PyModel> model, int s, int N, double dt, const std::string& controls) {
           return new PV(std::move(model), s, N, dt, parse_controls(controls));
         }),
         py::arg("model"), py::arg("s"), py::arg("N"), py::arg("dt"), py::arg("controls") = "per_point",
         "N stages of the order-2s VI with step dt on a copy of `model`; controls 'per_point' or 'held'.")
      .def_property_readonly("offsets", [](const PV& p) {
            py::typing::Dict<py::str, int> d;
            d["q"] = p.t.q_offset();
            d["p"] = p.t.p_offset();
            d["u"] = p.t.u_offset();
            d["lambda"] = p.t.lambda_offset();
            d["holonomic_row"] = p.t.holonomic_row();
            return d;
          }, "Offsets of the variable blocks in x and of the first holonomic row.")
      .def_property_readonly("n_points", [](const PV& p) { return p.t.n_points(); }, "Number of control points N s + 1.")
      .def_property_readonly("n_control_values", [](const PV& p) { return p.t.n_control_values(); },
                             "Number of control samples (per point or per stage).");
  bind_common(vi);

  using PH = PyTranscription<HermiteSimpsonTranscription>;
  py::class_<PH> hs(t, "HermiteSimpsonTranscription", R"doc(
Hermite-Simpson collocation as NLP constraints (hermite_simpson_transcription.hpp), implicit (a as
variables, inverse-dynamics rows) or explicit (a = forward dynamics inside the collocation rows):
variables q, v (and a) at the 2N + 1 knots and midpoints, controls, multipliers at every point.
)doc");
  hs.def(py::init([](std::shared_ptr<PyModel> model, int N, double dt, const std::string& controls, bool implicit) {
           return new PH(std::move(model), N, dt, parse_controls(controls), implicit);
         }),
         py::arg("model"), py::arg("N"), py::arg("dt"), py::arg("controls") = "per_point", py::arg("implicit") = true,
         "N Hermite-Simpson intervals of length dt on a copy of `model`; controls 'per_point' or 'held'.")
      .def_property_readonly("offsets", [](const PH& p) {
            py::typing::Dict<py::str, int> d;
            d["q"] = p.t.q_offset();
            d["v"] = p.t.v_offset();
            if (p.t.implicit()) d["a"] = p.t.a_offset();
            d["u"] = p.t.u_offset();
            d["lambda"] = p.t.lambda_offset();
            return d;
          }, "Offsets of the variable blocks in x.")
      .def_property_readonly("n_points", [](const PH& p) { return p.t.n_points(); }, "Number of points 2N + 1 (knots and midpoints).")
      .def_property_readonly("n_control_values", [](const PH& p) { return p.t.n_control_values(); },
                             "Number of control samples (per point or per interval).");
  bind_common(hs);
  bind_row_blocks(t);
  bind_nlp_program(t);
}

}  // namespace hovi::py_bind
