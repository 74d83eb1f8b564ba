// The extension module hovi._core: exception classes and one bind_* call per area.
#include "common.hpp"
#include "hovi/errors.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_core, m) {
  m.doc() = "hovi C++ core: higher-order variational integrators for robots";
  m.attr("march") = HOVI_ARCH;  // -march of the build (CMake's HOVI_ARCH; "" = the compiler's default)
  static py::exception<hovi::ModelError> model_error(m, "ModelError", PyExc_ValueError);
  static py::exception<hovi::UrdfError> urdf_error(m, "URDFError", model_error.ptr());
  model_error.attr("__doc__") =
      "An invalid model or model input (a ValueError): a bad body, joint, force or constraint, an unknown "
      "joint or body name, or a call on an Integrator or Linearizer whose model changed after it was made.";
  urdf_error.attr("__doc__") = "A URDF that cannot be loaded (a ModelError); the message names the link or joint at fault.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const hovi::UrdfError& e) {
      py::set_error(urdf_error, e.what());
    } catch (const hovi::ModelError& e) {
      py::set_error(model_error, e.what());
    } catch (const hovi::InputError& e) {
      py::set_error(PyExc_ValueError, e.what());
    }
  });
  m.def("real_array", [](const hovi::py_bind::ArrayLike& x, const std::string& name) {
        return hovi::py_bind::real_array(x, name.c_str());
      }, py::arg("x"), py::arg("name"),
      "x: an array of any shape, e.g. (n,) or (B, n); returns it as float64 (the same shape), as every array "
      "argument of hovi._core is read: ValueError naming `name` "
      "for complex numbers (never cast to real), text, Python objects (None is not NaN), booleans, None or a ragged "
      "list. The values are not checked (NaN passes).");
  hovi::py_bind::bind_model(m);
  hovi::py_bind::bind_contact(m);  // before the integrator and the rows, whose signatures name ContactModel
  hovi::py_bind::bind_integrator(m);
  hovi::py_bind::bind_linearizer(m);
  hovi::py_bind::bind_trajopt(m);
  hovi::py_bind::bind_control(m);
}
