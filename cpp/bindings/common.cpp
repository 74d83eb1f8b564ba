#include "common.hpp"

#include <sstream>

#include "hovi/errors.hpp"

namespace hovi::py_bind {

namespace {
std::string shape_of(const py::array& a) {
  std::ostringstream os;
  os << "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) os << (k ? ", " : "") << a.shape(k);
  os << (a.ndim() == 1 ? ",)" : ")");
  return os.str();
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()); }
}  // namespace

RealArray real_array(const py::handle& obj, const char* name) {
  if (PyComplex_Check(obj.ptr())) throw InputError(std::string(name) + " must be real, got a complex number");
  if (obj.is_none()) throw InputError(std::string(name) + " must be an array of real numbers, got None");
  py::array a;
  if (py::isinstance<py::array>(obj)) {
    a = py::reinterpret_borrow<py::array>(obj);
  } else {
    try {
      a = py::module_::import("numpy").attr("asarray")(obj);
    } catch (py::error_already_set& e) {  // ragged nested lists, objects numpy cannot read
      throw InputError(std::string(name) + " must be an array of real numbers (numpy cannot read it as an array: " +
                       std::string(py::str(e.value())) + ")");
    }
  }
  // Anything but integers and floats would be cast to real silently by a forced cast: complex numbers
  // lose their imaginary part, strings are parsed, None reads as NaN, booleans as 0 and 1.
  switch (a.dtype().kind()) {
    case 'f': case 'i': case 'u': break;
    case 'c': throw InputError(std::string(name) + " must be an array of real numbers, got complex (" + dtype_text(a) + ")");
    case 'O': {
      std::string first;
      if (a.size()) first = ", e.g. " + std::string(py::repr(a.attr("flat")[py::int_(0)]));
      throw InputError(std::string(name) + " must be an array of real numbers, got an object array (dtype object" +
                       first + ")");
    }
    case 'U': case 'S':
      throw InputError(std::string(name) + " must be an array of real numbers, got text (" + dtype_text(a) + ")");
    case 'b': throw InputError(std::string(name) + " must be an array of real numbers, got booleans");
    default: throw InputError(std::string(name) + " must be an array of real numbers, got dtype " + dtype_text(a));
  }
  auto d = RealArray::ensure(a);
  if (!d) throw InputError(std::string(name) + " must be an array of real numbers");
  return d;
}

namespace {
// Values beyond this magnitude overflow products of states and inertias (v^2, M v): no physical input is near it.
constexpr double kMaxInput = 1e150;

template <class M>
void check_values(const M& m, const char* name) {
  if (!m.allFinite()) throw InputError(std::string(name) + " contains NaN or infinity");
  if (m.size() && m.cwiseAbs().maxCoeff() > kMaxInput)
    throw InputError(std::string(name) + " has an entry beyond 1e150 in magnitude (the arithmetic would overflow)");
}
}  // namespace

VecX as_vector(const py::handle& obj, const char* name, long n) {
  const RealArray a = real_array(obj, name);
  if (a.ndim() != 1 || (n >= 0 && a.shape(0) != n)) {
    std::ostringstream os;
    os << name << " must be a 1-D array";
    if (n >= 0) os << " of length " << n;
    os << ", got shape " << shape_of(a);
    throw InputError(os.str());
  }
  VecX v = Eigen::Map<const VecX>(a.data(), a.shape(0));
  check_values(v, name);
  return v;
}

MatX as_matrix(const py::handle& obj, const char* name, long rows, long cols) {
  const RealArray a = real_array(obj, name);
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols)) {
    std::ostringstream os;
    os << name << " must be a 2-D array of shape (" << (rows >= 0 ? std::to_string(rows) : "*") << ", "
       << (cols >= 0 ? std::to_string(cols) : "*") << "), got shape " << shape_of(a);
    throw InputError(os.str());
  }
  using RowMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  MatX m = Eigen::Map<const RowMat>(a.data(), a.shape(0), a.shape(1));
  check_values(m, name);
  return m;
}

double real_arg(const py::handle& obj, const char* name) {
  if (py::isinstance<py::bool_>(obj) || !(py::isinstance<py::float_>(obj) || PyIndex_Check(obj.ptr())))
    throw InputError(std::string(name) + " must be a real number, got " +
                     std::string(py::str(py::type::of(obj).attr("__name__"))) + " " + std::string(py::repr(obj)).substr(0, 60));
  return obj.cast<double>();
}

int threads_arg(const py::handle& threads) {
  if (threads.is_none()) return 0;
  if (py::isinstance<py::bool_>(threads) || !PyIndex_Check(threads.ptr()))
    throw InputError("threads must be a positive integer or None, got " + std::string(py::str(py::type::of(threads).attr("__name__"))));
  const auto i = py::reinterpret_steal<py::object>(PyNumber_Index(threads.ptr()));
  if (!i) throw py::error_already_set();
  int overflow = 0;
  const long long t = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow || t < 1 || t > 1 << 16)
    throw InputError("threads must be a positive integer (None: HOVI_NUM_THREADS or every core), got " +
                     std::string(py::str(threads)));
  return static_cast<int>(t);
}

py::list error_list(const std::vector<std::string>& errors) {
  py::list out;
  for (const auto& e : errors) out.append(e.empty() ? py::object(py::none()) : py::str(e));
  return out;
}

py::array_t<double> stack(const std::vector<Mat4>& mats) {
  py::array_t<double> out({static_cast<py::ssize_t>(mats.size()), py::ssize_t(4), py::ssize_t(4)});
  auto r = out.mutable_unchecked<3>();
  for (std::size_t k = 0; k < mats.size(); ++k)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) r(k, i, j) = mats[k](i, j);
  return out;
}

py::array_t<double> stack(const std::vector<MatX>& mats) {
  const py::ssize_t K = py::ssize_t(mats.size()), R = K ? mats[0].rows() : 0, C = K ? mats[0].cols() : 0;
  py::array_t<double> out({K, R, C});
  auto r = out.mutable_unchecked<3>();
  for (py::ssize_t k = 0; k < K; ++k)
    for (py::ssize_t i = 0; i < R; ++i)
      for (py::ssize_t j = 0; j < C; ++j) r(k, i, j) = mats[k](i, j);
  return out;
}

py::array_t<double> stack(const std::vector<Vec6>& vecs) {
  py::array_t<double> out({static_cast<py::ssize_t>(vecs.size()), py::ssize_t(6)});
  auto r = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < vecs.size(); ++k)
    for (int i = 0; i < 6; ++i) r(k, i) = vecs[k](i);
  return out;
}

}  // namespace hovi::py_bind
