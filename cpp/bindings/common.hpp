// Shared helpers of the pybind11 bindings: array conversion with clear errors.
#pragma once
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/typing.h>

#include "hovi/spatial/types.hpp"

namespace hovi::py_bind {
namespace py = pybind11;

// Argument types for the signatures (and so the type stubs): each accepts any Python object, as
// py::object does, and is checked by the code that reads it (as_vector, joint_arg, ...); only its
// name in the signature differs, e.g. `q: numpy.typing.ArrayLike`.
inline int any_object(PyObject*) { return 1; }
#define HOVI_PY_HINTED_OBJECT(Name)                            \
  class Name : public py::object {                             \
    PYBIND11_OBJECT_DEFAULT(Name, object, any_object)          \
    using object::object;                                      \
  };
HOVI_PY_HINTED_OBJECT(ArrayLike)     // numpy.typing.ArrayLike: read by as_vector / as_matrix
HOVI_PY_HINTED_OBJECT(OptArrayLike)  // numpy.typing.ArrayLike | None
HOVI_PY_HINTED_OBJECT(Index)         // int | str: a joint or body by index or name
HOVI_PY_HINTED_OBJECT(OptIndex)      // int | str | None
HOVI_PY_HINTED_OBJECT(PathOrXml)     // str | os.PathLike[str]: a URDF path or XML string
HOVI_PY_HINTED_OBJECT(OptInt)        // int | None
HOVI_PY_HINTED_OBJECT(Real)          // float: read by real_arg
HOVI_PY_HINTED_OBJECT(AnyTranscription)  // hovi._core.trajopt.VariationalTranscription | ...HermiteSimpsonTranscription
HOVI_PY_HINTED_OBJECT(OptArrayFunction)   // a Python function of an array, or None
HOVI_PY_HINTED_OBJECT(CsrArrays)     // (indptr, indices, data) of a matrix in compressed rows
#undef HOVI_PY_HINTED_OBJECT

// Typed containers for return values: py::typing::Tuple<MatX, VecX> is `tuple[NDArray, NDArray]`.
template <class... T>
using Tuple = py::typing::Tuple<T...>;
template <class T>
using Optional = py::typing::Optional<T>;
using StrDict = py::typing::Dict<py::str, py::object>;  // dict[str, typing.Any]

// A C-ordered float64 numpy array.
using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
// obj (an array, list, ...) as a RealArray of any shape, values unchecked; InputError (ValueError)
// naming `name` unless numpy reads it as integers or floats: complex numbers (whose imaginary part a
// cast would drop), text (which a cast would parse), Python objects (None would read as NaN),
// booleans, None and ragged lists are refused. Every array argument of the bindings goes through it.
RealArray real_array(const py::handle& obj, const char* name);
// A 1-D real array of length n (n < 0: any length) converted to VecX; ValueError otherwise, and for
// what real_array refuses, non-finite or overflowing (beyond 1e150) values.
VecX as_vector(const py::handle& obj, const char* name, long n);
// A 2-D real array of shape (rows, cols) (negative: any) converted to MatX; ValueError as as_vector.
MatX as_matrix(const py::handle& obj, const char* name, long rows, long cols);
// A real number given as float | int (Real), values unchecked; InputError naming `name` for a bool,
// text, None or anything else Python does not read as a real number.
double real_arg(const py::handle& obj, const char* name);
// A thread count given as int | None (OptInt) for the batched calls: None -> 0 (HOVI_NUM_THREADS or
// every core, parallel_for.hpp's thread_count); ValueError unless a positive integer.
int threads_arg(const py::handle& threads);
// The per-item errors of a batch (parallel_for.hpp) as a list: None where an item finished, else its message.
py::list error_list(const std::vector<std::string>& errors);
// A stack of SE(3)/4x4 or 6-vectors as numpy arrays of shape (n, 4, 4) / (n, 6).
py::array_t<double> stack(const std::vector<Mat4>& mats);
py::array_t<double> stack(const std::vector<MatX>& mats);  // K equal-sized matrices -> (K, rows, cols)
py::array_t<double> stack(const std::vector<Vec6>& vecs);

void bind_model(py::module_& m);
void bind_integrator(py::module_& m);
void bind_linearizer(py::module_& m);
void bind_trajopt(py::module_& m);
void bind_nlp_program(py::module_& trajopt);  // into hovi._core.trajopt
void bind_row_blocks(py::module_& trajopt);   // into hovi._core.trajopt
void bind_contact(py::module_& m);
void bind_control(py::module_& m);

}  // namespace hovi::py_bind

namespace pybind11::detail {
#define HOVI_PY_TYPE_NAME(Name, Text) \
  template <>                         \
  struct handle_type_name<hovi::py_bind::Name> { static constexpr auto name = const_name(Text); };
HOVI_PY_TYPE_NAME(ArrayLike, "numpy.typing.ArrayLike")
HOVI_PY_TYPE_NAME(OptArrayLike, "numpy.typing.ArrayLike | None")
HOVI_PY_TYPE_NAME(Index, "int | str")
HOVI_PY_TYPE_NAME(Real, "float")
HOVI_PY_TYPE_NAME(OptIndex, "int | str | None")
HOVI_PY_TYPE_NAME(PathOrXml, "str | os.PathLike[str]")
HOVI_PY_TYPE_NAME(OptInt, "int | None")
HOVI_PY_TYPE_NAME(AnyTranscription,
                  "hovi._core.trajopt.VariationalTranscription | hovi._core.trajopt.HermiteSimpsonTranscription")
HOVI_PY_TYPE_NAME(CsrArrays, "tuple[numpy.typing.ArrayLike, numpy.typing.ArrayLike, numpy.typing.ArrayLike]")
HOVI_PY_TYPE_NAME(OptArrayFunction,
                  "collections.abc.Callable[[numpy.typing.NDArray[numpy.float64]], typing.Any] | None")
#undef HOVI_PY_TYPE_NAME
}  // namespace pybind11::detail
