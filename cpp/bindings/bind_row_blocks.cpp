// Bindings of the built-in rows of the NLP program (hovi._core.trajopt.RowBlock and its kinds):
// python/hovi/trajopt/nlp.py makes them for the body-point path constraints and the contact rows
// and places them in the Program.
#include "hovi/trajopt/body_point_rows.hpp"
#include "hovi/trajopt/complementarity_rows.hpp"
#include "py_contact.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

namespace {
VecX vector_of(const RowBlock& b, const ArrayLike& x) { return as_vector(x, "x", b.n_variables()); }
}  // namespace

void bind_row_blocks(py::module_& t) {
  py::class_<RowBlock, std::shared_ptr<RowBlock>>(t, "RowBlock", R"doc(
Constraint rows beside the transcription that C++ evaluates with their own exact Hessian
(row_block.hpp); a Program places them.
)doc")
      .def_property_readonly("rows", &RowBlock::rows, "Number of rows.")
      .def_property_readonly("nnz", &RowBlock::nnz, "Number of Jacobian values.")
      .def("values", [](const RowBlock& b, const ArrayLike& x) {
             VecX g(b.rows());
             b.values(vector_of(b, x), g);
             return g;
           }, py::arg("x"), "x (n_variables,): the rows' values (rows,).")
      .def("jacobian", [](const RowBlock& b, const ArrayLike& x) {
             VecX v(b.nnz());
             b.jacobian(vector_of(b, x), v);
             return v;
           }, py::arg("x"), "x (n_variables,): the Jacobian's values (nnz,) in the order the NLP lists its structure.")
      .def_property_readonly("hessian_structure", [](const RowBlock& b) {
             return py::make_tuple(b.hessian_structure().rows, b.hessian_structure().cols);
           }, "(rows, cols) of the Hessian's lower-triangle entries (an entry may repeat; the values add).")
      .def("hessian", [](const RowBlock& b, const ArrayLike& x, const ArrayLike& lam) {
             VecX v(b.hessian_structure().nnz());
             b.hessian(vector_of(b, x), as_vector(lam, "lam", b.rows()), v);
             return v;
           }, py::arg("x"), py::arg("lam"), "x (n_variables,), lam (rows,): the Hessian of lam . rows at hessian_structure.");
  py::class_<BodyPointRows, RowBlock, std::shared_ptr<BodyPointRows>>(t, "BodyPointRows", R"doc(
Path constraints on body points sharing a set of configurations, each a weighted sum of the
transcription's configuration points (body_point_rows.hpp): row (p, i) = c_i + sum_m L[i, m] . x_b
+ D[i, m] . x_b^2 with b = idx[i, m], x_b the world position of body point b at configuration p.
)doc")
      .def(py::init([](std::shared_ptr<PyModel> model, int n_variables, const IndexMatrix& offsets, const ArrayLike& weights,
                       const std::vector<int>& bodies, const ArrayLike& local, const ArrayLike& c, const ArrayLike& L,
                       const ArrayLike& D, const IndexMatrix& idx) {
             const long R = static_cast<long>(idx.rows()) * idx.cols();
             return std::make_shared<BodyPointRows>(
                 model->model, n_variables, offsets, as_matrix(weights, "weights", offsets.rows(), offsets.cols()), bodies,
                 as_matrix(local, "local", static_cast<long>(bodies.size()), 3), as_vector(c, "c", idx.rows()),
                 as_matrix(L, "L", R, 3), as_matrix(D, "D", R, 3), idx);
           }),
           py::arg("model"), py::arg("n_variables"), py::arg("offsets"), py::arg("weights"), py::arg("bodies"),
           py::arg("local"), py::arg("c"), py::arg("L"), py::arg("D"), py::arg("idx"),
           "offsets (P, K): where q of configuration p's k-th point starts in x; weights (P, K); bodies (B,), local "
           "(B, 3): the points; c (R,), L and D (R M, 3), idx (R, M): the rows' form (path_constraints.OnBodyPoints).");
  py::class_<ComplementarityRows, RowBlock, std::shared_ptr<ComplementarityRows>>(t, "ComplementarityRows", R"doc(
The contact complementarity rows of hovi.trajopt.ContactRows (complementarity_rows.hpp), values,
Jacobian in its structure's order and exact Hessian.
)doc")
      .def(py::init([](std::shared_ptr<PyModel> model, int n_variables, const ContactModel& contacts, int first_input,
                       const ArrayLike& t, const Eigen::VectorXi& q_off, const Eigen::VectorXi& u_off) {
             return std::make_shared<ComplementarityRows>(model->model, n_variables, contacts, first_input,
                                                          as_vector(t, "t", q_off.size()), q_off, u_off);
           }),
           py::arg("model"), py::arg("n_variables"), py::arg("contacts"), py::arg("first_input"), py::arg("t"),
           py::arg("q_off"), py::arg("u_off"),
           "The contacts (hovi.contact.Contacts.core_model()) on `model` (Contacts.with_inputs); first_input: the control "
           "index of the first contact input; t, q_off, u_off (P,): the configuration points' times and offsets of q "
           "and u in x.");
}

}  // namespace hovi::py_bind
