// Binding of the NLP program (hovi._core.trajopt.Program): python/hovi/trajopt/nlp.py builds it
// once per NLP; a solver (hovi._ipopt) then evaluates it without Python, except for the terms
// written in Python (the extra_* functions), one call per evaluation.
#include <Eigen/SparseCore>

#include "hovi/errors.hpp"
#include "hovi/trajopt/colouring.hpp"
#include "hovi/trajopt/hermite_simpson_transcription.hpp"
#include "hovi/trajopt/variational_transcription.hpp"
#include "py_program.hpp"
#include "py_transcription.hpp"

namespace hovi::py_bind {

namespace {

const Transcription& transcription_of(const py::object& obj) {
  if (py::isinstance<PyTranscription<VariationalTranscription>>(obj))
    return obj.cast<const PyTranscription<VariationalTranscription>&>().get();
  if (py::isinstance<PyTranscription<HermiteSimpsonTranscription>>(obj))
    return obj.cast<const PyTranscription<HermiteSimpsonTranscription>&>().get();
  throw InputError("transcription must be a hovi._core.trajopt.VariationalTranscription or "
                   "HermiteSimpsonTranscription");
}

// Copies a Python result into out (the expected length), naming the hook on a mismatch.
void copy_into(const py::handle& result, Eigen::Ref<VecX> out, const char* what) {
  const RealArray a = real_array(result, what);
  if (a.ndim() != 1 || a.shape(0) != out.size())
    throw InputError(std::string(what) + " must have shape (" + std::to_string(out.size()) + ",)");
  out = Eigen::Map<const VecX>(a.data(), out.size());
}

py::array_t<double> view(const VecX& x) { return py::array_t<double>(x.size(), x.data()); }

// The extra terms as C++ hooks that take the GIL and call the Python functions (each None or a
// callable of x; kept alive by PyProgram).
ExtraTerms extra_hooks(const PyProgram& p, const Eigen::VectorXi& rows, const Eigen::VectorXi& entries) {
  ExtraTerms e;
  if ((rows.size() != 0 || entries.size() != 0) && (p.extra_constraints.is_none() || p.extra_jacobian.is_none()))
    throw InputError("extra rows need extra_constraints and extra_jacobian functions");
  e.rows = rows;
  e.entries = entries;
  const auto borrowed = [](const py::object& f) {
    const PyObject* raw = f.ptr();
    return [raw] { return py::reinterpret_borrow<py::object>(const_cast<PyObject*>(raw)); };
  };
  if (!p.extra_cost.is_none()) {
    const auto f = borrowed(p.extra_cost);
    e.cost = [f](const VecX& x, Eigen::Ref<VecX> grad) {
      py::gil_scoped_acquire gil;
      py::tuple r = f()(view(x));
      VecX g(grad.size());
      copy_into(r[1], g, "the extra cost's gradient");
      grad += g;
      return r[0].cast<double>();
    };
  }
  if (rows.size() > 0) {
    const auto fc = borrowed(p.extra_constraints), fj = borrowed(p.extra_jacobian);
    e.constraints = [fc](const VecX& x, Eigen::Ref<VecX> g) {
      py::gil_scoped_acquire gil;
      copy_into(fc()(view(x)), g, "the extra constraints");
    };
    e.jacobian = [fj](const VecX& x, Eigen::Ref<VecX> v) {
      py::gil_scoped_acquire gil;
      copy_into(fj()(view(x)), v, "the extra Jacobian values");
    };
  }
  return e;
}

// Checks a pattern in compressed rows (indptr (rows+1,), indices < cols); InputError naming `what`.
void check_compressed(const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices, long cols, const std::string& what) {
  if (indptr.size() < 1 || indptr[0] != 0 || indptr[indptr.size() - 1] != indices.size())
    throw InputError(what + ": indptr must start at 0 and end at len(indices)");
  for (long i = 0; i + 1 < indptr.size(); ++i)
    if (indptr[i + 1] < indptr[i]) throw InputError(what + ": indptr must not decrease");
  if (indices.size() > 0 && (indices.minCoeff() < 0 || indices.maxCoeff() >= cols))
    throw InputError(what + ": column indices out of range");
}

// A symmetric pattern's (indptr, indices): square, so its columns are its rows.
Pattern square_pattern(const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices) {
  check_compressed(indptr, indices, static_cast<long>(indptr.size()) - 1, "the pattern");
  return Pattern{indptr, indices};
}

// A matrix in compressed rows given as (indptr (rows+1,), indices, data) with `cols` columns (a
// scipy.sparse.csr_matrix's arrays); InputError naming `name` unless consistent.
SparseRowMatrix csr_of(const py::handle& arrays, const char* name, int cols) {
  const std::string what(name);
  if (!py::isinstance<py::tuple>(arrays) || py::len(arrays) != 3)
    throw InputError(what + " must be a tuple (indptr, indices, data) of a matrix in compressed rows");
  const py::tuple t = py::reinterpret_borrow<py::tuple>(arrays);
  const Eigen::VectorXi indptr = t[0].cast<Eigen::VectorXi>(), indices = t[1].cast<Eigen::VectorXi>();
  const VecX data = as_vector(t[2], (what + " data").c_str(), indices.size());
  check_compressed(indptr, indices, cols, what);
  return Eigen::Map<const SparseRowMatrix>(static_cast<long>(indptr.size()) - 1, cols, static_cast<long>(indices.size()),
                                           indptr.data(), indices.data(), data.data());
}

// The blocks as (RowBlock, rows (its rows' places in g), entries (its Jacobian values' places)) tuples.
std::vector<PlacedRows> placed_blocks(const py::list& blocks) {
  std::vector<PlacedRows> out;
  for (const py::handle& item : blocks) {
    if (!py::isinstance<py::tuple>(item) || py::len(item) != 3)
      throw InputError("blocks must be (RowBlock, rows, entries) tuples");
    const py::tuple t = py::reinterpret_borrow<py::tuple>(item);
    if (!py::isinstance<RowBlock>(t[0])) throw InputError("blocks: the first of each tuple must be a RowBlock");
    try {
      out.push_back({t[0].cast<std::shared_ptr<RowBlock>>(), t[1].cast<Eigen::VectorXi>(), t[2].cast<Eigen::VectorXi>()});
    } catch (const py::cast_error&) {
      throw InputError("blocks: a block's rows and entries must be 1-D arrays of integers");
    }
  }
  return out;
}

const NlpProgram& program_of(const PyProgram& p) { return *p.program; }

VecX vector_of(const PyProgram& p, const ArrayLike& x) { return as_vector(x, "x", p.program->n_variables()); }

}  // namespace

void bind_nlp_program(py::module_& t) {
  t.def("star_colouring", [](const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices) {
         return star_colouring(square_pattern(indptr, indices));
       }, py::arg("indptr"), py::arg("indices"),
       "Star colours (nv,) of the symmetric pattern in compressed rows (indptr (nv + 1,), indices) (colouring.hpp).");
  t.def("gram_pattern", [](const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices, int n) {
         if (n < 0) throw InputError("n must be >= 0, got " + std::to_string(n));
         check_compressed(indptr, indices, n, "the pattern");
         return gram_pattern(Pattern{indptr, indices}, n);
       }, py::arg("indptr"), py::arg("indices"), py::arg("n"),
       "The symmetric pattern (indptr (n+1,), indices) of A^T A + I for the pattern A in compressed rows "
       "(indptr, indices < n) (colouring.hpp).");
  t.def("distance2_colouring", [](const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices) {
         return distance2_colouring(square_pattern(indptr, indices));
       }, py::arg("indptr"), py::arg("indices"),
       "Distance-2 colours (nv,) of the symmetric pattern in compressed rows (indptr (nv + 1,), indices) (colouring.hpp).");
  py::class_<PyProgram>(t, "Program", R"doc(
The NLP of a transcribed problem evaluated in C++ (nlp_program.hpp), as hovi.trajopt.NLP lays it
out: the quadratic costs c + sum_i d_i (S x - r)_i^2 / 2, rows [transcription | extra | A x], the Jacobian
in `jac_rows`, `jac_cols` order, and the Lagrangian's Hessian by coloured differences once
`set_colouring` gave the colours. The built-in rows (path constraints on body points, contact rows)
are RowBlocks; the terms written in Python come through functions of x (each None when absent):
extra_cost(x) -> (value, gradient), extra_constraints(x) -> (len(extra_rows),), extra_jacobian(x) ->
(len(extra_entries),), one call per evaluation.
)doc")
      .def(py::init([](AnyTranscription transcription, double c, const CsrArrays& S_csr, const ArrayLike& r,
                       const ArrayLike& d, const CsrArrays& A_csr, const Eigen::VectorXi& jac_rows,
                       const Eigen::VectorXi& jac_cols, const py::list& blocks, OptArrayFunction extra_cost,
                       OptArrayFunction extra_constraints, OptArrayFunction extra_jacobian,
                       const Eigen::VectorXi& extra_rows, const Eigen::VectorXi& extra_entries) {
             const Transcription& tr = transcription_of(transcription);
             const SparseRowMatrix S = csr_of(S_csr, "S", tr.n_variables()), A = csr_of(A_csr, "A", tr.n_variables());
             auto p = std::make_unique<PyProgram>();
             p->transcription = transcription;
             p->extra_cost = extra_cost;
             p->extra_constraints = extra_constraints;
             p->extra_jacobian = extra_jacobian;
             p->program = std::make_unique<NlpProgram>(tr, c, S, as_vector(r, "r", S.rows()), as_vector(d, "d", S.rows()), A,
                                                       placed_blocks(blocks), extra_hooks(*p, extra_rows, extra_entries),
                                                       jac_rows, jac_cols);
             return p;
           }),
           py::arg("transcription"), py::arg("c"), py::arg("S"), py::arg("r"), py::arg("d"), py::arg("A"), py::arg("jac_rows"),
           py::arg("jac_cols"), py::arg("blocks") = py::list(), py::arg("extra_cost") = OptArrayFunction(py::none()),
           py::arg("extra_constraints") = OptArrayFunction(py::none()),
           py::arg("extra_jacobian") = OptArrayFunction(py::none()), py::arg("extra_rows") = Eigen::VectorXi(),
           py::arg("extra_entries") = Eigen::VectorXi(),
           "transcription: the C++ transcription; c, S (k, n), r (k,), d (k,): the quadratic costs; A (a, n): the "
           "linear rows (S, A as (indptr, indices, data) in compressed rows); jac_rows, jac_cols (nnz,): the whole "
           "Jacobian's structure; blocks: (RowBlock, rows, entries) tuples, the built-in rows with the places of their "
           "rows in g and of their Jacobian values; the extra terms (see the class), their rows at extra_rows and "
           "Jacobian values at extra_entries. Between the transcription's rows and A's every place is taken once.")
      .def_property_readonly("n_variables", [](const PyProgram& p) { return p.program->n_variables(); }, "Length of x.")
      .def_property_readonly("n_constraints", [](const PyProgram& p) { return p.program->n_constraints(); }, "Length of g(x).")
      .def_property_readonly("nnz", [](const PyProgram& p) { return p.program->nnz(); }, "Jacobian nonzeros.")
      .def("objective", [](const PyProgram& p, const ArrayLike& x) { return program_of(p).objective(vector_of(p, x)); },
           py::arg("x"), "x: (n_variables,); the total cost.")
      .def("gradient", [](const PyProgram& p, const ArrayLike& x) {
             VecX g(p.program->n_variables());
             program_of(p).gradient(vector_of(p, x), g);
             return g;
           }, py::arg("x"), "x: (n_variables,); the cost's gradient (n_variables,).")
      .def("constraints", [](const PyProgram& p, const ArrayLike& x) {
             VecX g(p.program->n_constraints());
             program_of(p).constraints(vector_of(p, x), g);
             return g;
           }, py::arg("x"), "x: (n_variables,); g(x) (n_constraints,).")
      .def("jacobian", [](const PyProgram& p, const ArrayLike& x) {
             VecX v(p.program->nnz());
             program_of(p).jacobian(vector_of(p, x), v);
             return v;
           }, py::arg("x"), "x: (n_variables,); the Jacobian's values (nnz,) in (jac_rows, jac_cols) order.")
      .def("set_colouring", [](PyProgram& p, const Eigen::VectorXi& colour, const Eigen::VectorXi& rows,
                               const Eigen::VectorXi& cols, const Eigen::VectorXi& read_row,
                               const Eigen::VectorXi& read_col, const OptInt& threads, bool by_differences) {
             p.hessian = std::make_unique<LagrangianHessian>(*p.program,
                                                             HessianColouring{colour, rows, cols, read_row, read_col},
                                                             threads_arg(threads), by_differences);
           }, py::arg("colour"), py::arg("rows"), py::arg("cols"), py::arg("read_row"), py::arg("read_col"),
           py::arg("threads") = OptInt(py::int_(1)), py::arg("by_differences") = false,
           "colour (n_variables,); the lower triangle's entries rows >= cols (E,) and where each is read: component "
           "read_row of the difference of read_col's colour (hovi.trajopt.hessian.LagrangianHessian); threads: for "
           "the transcription's Hessian or its colours' differences (None: HOVI_NUM_THREADS or every core; the extra "
           "terms on the calling thread); by_differences: difference the transcription's and the built-in rows' parts "
           "even where they have Hessians of their own (the VI's, del_hessian.hpp; the RowBlocks').")
      .def("set_hessian_options", [](PyProgram& p, const OptInt& threads, bool by_differences) {
             if (!p.hessian) throw InputError("the program has no Hessian: call set_colouring first");
             p.hessian = std::make_unique<LagrangianHessian>(*p.program, p.hessian->colouring(), threads_arg(threads),
                                                             by_differences);
           }, py::arg("threads"), py::arg("by_differences"),
           "The Hessian's threads and whether it differences the parts that have Hessians of their own (as "
           "set_colouring), its colours kept.")
      .def_property_readonly("hessian_threads", [](const PyProgram& p) { return p.hessian ? p.hessian->threads() : 0; },
                             "Threads of the Hessian (0 without a Hessian).")
      .def_property_readonly("transcription_hessian",
                             [](const PyProgram& p) { return p.hessian && p.hessian->transcription_hessian(); },
                             "Whether the Hessian takes the transcription's part from its own Hessian (not differenced).")
      .def("probed_pattern", [](const PyProgram& p, const Eigen::VectorXi& indptr, const Eigen::VectorXi& indices,
                                const ArrayLike& x, unsigned seed, bool own_structures) {
             if (indptr.size() != p.program->n_variables() + 1)
               throw InputError("the pattern must have one row per variable");
             const VecX xv = vector_of(p, x);
             return probed_pattern(*p.program, square_pattern(indptr, indices), xv, seed, own_structures);
           }, py::arg("indptr"), py::arg("indices"), py::arg("x"), py::arg("seed") = 0, py::arg("own_structures") = false,
           "The entries (indptr, indices) of the symmetric coupling pattern (indptr (n_variables + 1,), indices) where "
           "the Lagrangian's Hessian is not identically zero, probed at a random point near x (n_variables,) "
           "(lagrangian_hessian.hpp), with the quadratic costs' entries and the diagonal; own_structures: the "
           "transcription's (if it has one) and the built-in rows' entries from their own Hessians' values at "
           "that point, only the rest probed.")
      .def_property_readonly("has_hessian", [](const PyProgram& p) { return bool(p.hessian); },
                             "Whether set_colouring gave the Hessian its colours.")
      .def("hessian", [](const PyProgram& p, const ArrayLike& x, const ArrayLike& lam, double sigma) {
             if (!p.hessian) throw InputError("the program has no Hessian: call set_colouring first");
             VecX v(p.hessian->nnz());
             p.hessian->values(vector_of(p, x), as_vector(lam, "lam", p.program->n_constraints()), sigma, v);
             return v;
           }, py::arg("x"), py::arg("lam"), py::arg("sigma"),
           "x (n_variables,), lam (n_constraints,), sigma: the lower triangle of the Lagrangian's Hessian (E,) at the "
           "colouring's entries.");
}

}  // namespace hovi::py_bind
