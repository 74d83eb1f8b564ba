// Bindings of the contact model (hovi._core.ContactModel): what hovi.contact.Contacts gives the
// integrator's contact stages and the trajectory optimiser's complementarity rows.
#include <string>
#include <vector>

#include "hovi/errors.hpp"
#include "hovi/forces/contact_inputs.hpp"
#include "py_contact.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

Terrain terrain(double ground, const ArrayLike& gaps, const ArrayLike& boxes) {
  Terrain t;
  t.ground = ground;
  const RealArray g = real_array(gaps, "gaps");
  if (g.size()) {
    const MatX G = as_matrix(gaps, "gaps (x0, x1, depth)", -1, 3);
    for (Eigen::Index i = 0; i < G.rows(); ++i) t.gaps.push_back({G(i, 0), G(i, 1), G(i, 2)});
  }
  const RealArray b = real_array(boxes, "boxes");
  if (b.size()) {  // y0, y1 may be infinite: read without as_matrix's finiteness check
    if (b.ndim() != 2 || b.shape(1) != 5) throw InputError("boxes must have shape (B, 5): x0, x1, top, y0, y1");
    auto r = b.unchecked<2>();
    for (py::ssize_t i = 0; i < b.shape(0); ++i) t.boxes.push_back({r(i, 0), r(i, 1), r(i, 2), r(i, 3), r(i, 4)});
  }
  t.check();
  return t;
}

ContactModel contact_model(const std::vector<int>& bodies, const ArrayLike& points, const Terrain& terrain, double mu,
                           const ArrayLike& directions, const OptArrayLike& radii) {
  ContactModel cm;
  const long C = static_cast<long>(bodies.size());
  const MatX P = as_matrix(points, "points", C, 3);
  const VecX r = radii.is_none() ? VecX::Zero(C) : as_vector(radii, "radii", C);
  for (long i = 0; i < C; ++i) cm.points.push_back({bodies[i], P.row(i).transpose(), r[i]});
  cm.terrain = terrain;
  cm.mu = mu;
  cm.D = as_matrix(directions, "friction directions", -1, 3);
  return cm;
}

void bind_contact(py::module_& m) {
  py::class_<Terrain>(m, "Terrain", R"doc(
The terrain of the contact model (model/contact_model.hpp): a ground plane with gaps and boxes, all
with horizontal top faces; the one home of its height. hovi.contact.Terrain makes it (Terrain.core()).
)doc")
      .def(py::init(&terrain), py::arg("ground"), py::arg("gaps"), py::arg("boxes"), R"doc(
The ground height, gaps (G, 3) rows (x0, x1, depth), boxes (B, 5) rows (x0, x1, top, y0, y1) (y0, y1 may
be infinite); ValueError naming the field of a bad one.
)doc")
      .def("heights", [](const Terrain& t, const ArrayLike& xy) {
            const RealArray a = real_array(xy, "xy");
            if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 2) throw InputError("xy must have shape (..., 2)");
            std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim() - 1);
            py::array_t<double> out(shape);
            const double* in = a.data();
            double* o = out.mutable_data();
            for (py::ssize_t k = 0; k < out.size(); ++k) o[k] = t.height(in[2 * k], in[2 * k + 1]);
            return out;
          }, py::arg("xy"), "The height h(x, y) of the surface below points xy (..., 2): (...).");
  py::class_<ContactModel>(m, "ContactModel", R"doc(
Point contacts with a terrain and Coulomb friction on a polyhedral cone (model/contact_model.hpp),
fixed once made: hovi.contact.Contacts makes it (Contacts.core_model()) for hovi.Integrator(...,
contacts=...) and the trajectory optimiser's complementarity rows.
)doc")
      .def(py::init(&contact_model), py::arg("bodies"), py::arg("points"), py::arg("terrain"), py::arg("mu"),
           py::arg("directions"), py::arg("radii") = py::none(), R"doc(
bodies (C,) indices, points (C, 3) in the bodies' joint frames; the terrain; friction mu; directions (d, 3)
horizontal unit vectors; radii (C,) of the contacts (spheres centred at the points, default 0: points).
)doc")
      .def("gaps", [](const ContactModel& c, const ArrayLike& X) {
            const RealArray a = real_array(X, "X");
            const int C = c.size();
            if (a.ndim() < 2 || a.shape(a.ndim() - 1) != 3 || a.shape(a.ndim() - 2) != C)
              throw InputError("X must have shape (..., " + std::to_string(C) + ", 3): the contact points' world positions");
            std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim() - 1);
            py::array_t<double> out(shape);
            const double* in = a.data();
            double* o = out.mutable_data();
            for (py::ssize_t k = 0; k < out.size(); ++k)
              o[k] = c.gap(static_cast<int>(k % C), Vec3(in[3 * k], in[3 * k + 1], in[3 * k + 2]));
            return out;
          }, py::arg("X"), "The gaps φ (K, C) of the contacts with their points at world positions X (K, C, 3) (any leading shape).")
      .def_property_readonly("n_contacts", &ContactModel::size, "The number of contact points C.")
      .def_property_readonly("per_contact", &ContactModel::per_contact,
                             "The unknowns per contact, 2 + d: the normal impulse, d friction impulses, the sliding slack.")
      .def("world_impulses", [](const ContactModel& c, const ArrayLike& z) {
            const MatX Z = as_matrix(z, "z (K, C (2 + d))", -1, c.unknowns());
            py::array_t<double> out(std::vector<py::ssize_t>{Z.rows(), c.size(), 3});
            auto w = out.mutable_unchecked<3>();
            for (Eigen::Index k = 0; k < Z.rows(); ++k) {
              const VecX zk = Z.row(k).transpose();
              for (int i = 0; i < c.size(); ++i) {
                const Vec3 F = c.world_impulse(zk, i);
                for (int j = 0; j < 3; ++j) w(k, i, j) = F[j];
              }
            }
            return out;
          }, py::arg("z"), R"doc(
The world impulses (or forces) (K, C, 3) of the contact unknowns z (K, C (2 + d)), per contact
λ e_z + D^T β (the slack γ carries none).
)doc")
      .def("index", [](const ContactModel& cm, int c, const std::string& what, int i) {
            if (c < 0 || c >= cm.size())
              throw InputError("c must be a contact index in [0, " + std::to_string(cm.size()) + "), got " + std::to_string(c));
            if (what == "normal") return cm.index(c, ContactUnknown::Normal);
            if (what == "slack") return cm.index(c, ContactUnknown::Slack);
            if (what != "friction") throw InputError("what must be 'normal', 'friction' or 'slack', got '" + what + "'");
            if (i < 0 || i >= cm.d())
              throw InputError("i must be a friction direction in [0, " + std::to_string(cm.d()) + "), got " + std::to_string(i));
            return cm.index(c, ContactUnknown::Friction, i);
          }, py::arg("c"), py::arg("what"), py::arg("i") = 0, R"doc(
The index among a step's unknowns (C (2 + d),) of contact c's 'normal' impulse, 'friction' impulse
along direction i, or 'slack'; as a control of with_inputs(model), it is model.n_controls + index.
)doc")
      .def("with_inputs", [](const ContactModel& cm, const PyModel& model) {
            auto out = std::make_shared<PyModel>();
            out->model = with_contact_inputs(model.model, cm);
            return out;
          }, py::arg("model"), R"doc(
A copy of `model` with the contacts' unknowns appended as controls (contact-implicit trajectory
optimisation), at model.n_controls + index(c, what, i): each normal and friction input scales a world
force (+z, or the friction direction) at the contact point; the slack has no force.
)doc");
}

}  // namespace hovi::py_bind
