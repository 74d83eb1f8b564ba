// Bindings of Model (with a private workspace), the URDF loader and the built-in models.
#include <memory>

#include "py_model.hpp"
#include "hovi/algorithms/body_points.hpp"
#include "hovi/algorithms/dynamics.hpp"
#include "hovi/algorithms/energy.hpp"
#include "hovi/algorithms/free_base.hpp"
#include "hovi/algorithms/stacked_constraints.hpp"
#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/algorithms/force_jacobians.hpp"
#include "hovi/algorithms/gravity_hessian.hpp"
#include "hovi/algorithms/kinetic_hessians.hpp"
#include "hovi/algorithms/kinematics.hpp"
#include "hovi/algorithms/mass_matrix.hpp"
#include "hovi/errors.hpp"
#include "hovi/parsers/model_serialization.hpp"
#include "hovi/models/pendulum.hpp"
#include "hovi/parsers/urdf.hpp"

namespace hovi::py_bind {

using namespace pybind11::literals;  // "name"_a = value: the keyword arguments of the result dicts

namespace {
// The index of a joint or body given by name (looked up by `index_of`) or by number.
template <class Lookup>
int index_arg(const Model& model, const py::handle& obj, const char* what, Lookup&& index_of) {
  if (py::isinstance<py::str>(obj)) {
    const std::string name = obj.cast<std::string>();
    const int i = index_of(name);
    if (i < 0) throw ModelError(std::string("no ") + what + " named '" + name + "'");
    return i;
  }
  const int i = obj.cast<int>();
  if (i < 0 || i >= model.n()) throw ModelError(std::string(what) + " index " + std::to_string(i) + " out of range");
  return i;
}
}  // namespace

int joint_arg(const Model& model, const py::handle& joint) {
  return index_arg(model, joint, "joint", [&](const std::string& n) { return model.joint_index(n); });
}

int body_arg(const Model& model, const py::handle& body) {
  return index_arg(model, body, "body", [&](const std::string& n) { return model.body_index(n); });
}

namespace {

const char* type_name(JointType t) { return t == JointType::Revolute ? "revolute" : "prismatic"; }

JointType parse_type(const std::string& t) {
  if (t == "revolute" || t == "continuous") return JointType::Revolute;
  if (t == "prismatic") return JointType::Prismatic;
  throw ModelError("joint_type must be 'revolute' or 'prismatic', got '" + t + "'");
}

}  // namespace

VecX PyModel::config(const py::handle& q) {
  if (model.rotation_chart < 0) return vec(q, "q");
  const VecX q_pub = as_vector(q, "q", model.nq());
  VecX out(model.n());
  FreeBase(model).split(q_pub, out, attitude);
  ws().chart_placement = model.chart_placement(attitude);
  return out;
}

VecX PyModel::velocity(const VecX& q, const py::handle& v, const char* name) {
  VecX out = vec(v, name);
  if (model.rotation_chart >= 0) FreeBase(model).velocity_to_chart(q, attitude, out);
  return out;
}

MatX PyModel::velocity_map(const VecX& q) {
  MatX T = MatX::Identity(model.n(), model.n());
  const FreeBase base(model);
  for (int i = 0; i < model.n(); ++i) base.velocity_to_chart(q, attitude, T.col(i));
  return T;
}

void PyModel::chart_coordinates_only(const char* what) const {
  if (model.rotation_chart >= 0)
    throw ModelError(std::string(what) + " is not available for a model with a free base yet (it is in joint "
                     "coordinates; load the robot with base='euler' for them)");
}

namespace {

BaseJoint parse_base(const std::string& b) {
  if (b == "fixed") return BaseJoint::Fixed;
  if (b == "floating") return BaseJoint::Floating;
  if (b == "euler") return BaseJoint::Euler;
  if (b == "planar") return BaseJoint::Planar;
  throw InputError("base must be 'fixed', 'floating', 'euler' or 'planar', got '" + b + "'");
}

SE3 as_se3(const py::handle& obj, const char* name) {
  const MatX T = as_matrix(obj, name, 4, 4);
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-12)
    throw InputError(std::string(name) + " must be a homogeneous transform (last row 0 0 0 1)");
  return SE3(T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>());
}

std::string summary(const Model& model) {
  std::ostringstream os;
  os << "hovi.Model: " << model.n() << " DoF, " << model.n() << " bodies, total mass " << model.total_mass()
     << " kg, gravity (" << model.gravity.transpose() << ")\n";
  os << "  #  body                      joint                     type       parent\n";
  for (int i = 0; i < model.n(); ++i) {
    const BodySpec& s = model.spec[i];
    char line[256];
    std::snprintf(line, sizeof line, "  %-2d %-25s %-25s %-10s %s\n", i, s.name.c_str(), s.joint_name.c_str(),
                  type_name(s.type), s.parent >= 0 ? model.spec[s.parent].name.c_str() : "world");
    os << line;
  }
  return os.str();
}

const char* const kShapeNames[] = {"box", "cylinder", "sphere", "mesh"};

StrDict visual_dict(const Visual& v) {
  StrDict d("body"_a = v.body, "link"_a = v.link, "shape"_a = kShapeNames[static_cast<int>(v.shape)],
            "size"_a = VecX(v.size), "filename"_a = v.filename, "scale"_a = VecX(v.scale),
            "origin"_a = Mat4(v.origin.matrix()), "rgba"_a = v.rgba ? py::cast(VecX(*v.rgba)) : py::none());
  return d;
}

// A Visual from add_visual's arguments; sizes as the shape takes them (box 3, cylinder 2, sphere 1).
Visual make_visual(const Model& model, const py::object& body, const std::string& shape, const py::object& size,
                   const py::object& origin, const py::object& rgba, const std::string& filename,
                   const py::object& scale, const std::string& link) {
  Visual v;
  v.body = body.is_none() ? -1 : body_arg(model, body);
  v.link = link.empty() ? (v.body >= 0 ? model.spec[v.body].name : std::string("world")) : link;
  int k = 0;
  while (k < 4 && shape != kShapeNames[k]) ++k;
  if (k == 4) throw InputError("shape must be 'box', 'cylinder', 'sphere' or 'mesh', got '" + shape + "'");
  v.shape = static_cast<VisualShape>(k);
  const int n_size[] = {3, 2, 1, 0};
  const bool scalar = py::isinstance<py::float_>(size) || py::isinstance<py::int_>(size);
  if (n_size[k] > 0) v.size.head(n_size[k]) = as_vector(scalar ? py::make_tuple(size) : size, "size", n_size[k]);
  if (!origin.is_none()) v.origin = as_se3(origin, "origin");
  if (!rgba.is_none()) v.rgba = Eigen::Vector4d(as_vector(rgba, "rgba", 4));
  v.filename = filename;
  v.scale = as_vector(scale, "scale", 3);
  return v;
}

// The force elements and constraints are immutable and shared; everything else is copied.
std::shared_ptr<PyModel> copy_of(const PyModel& s) {
  auto pm = std::make_shared<PyModel>();
  pm->model = s.model;
  return pm;
}

template <class F>
std::vector<std::string> per_body(const Model& model, F&& f) {
  std::vector<std::string> out;
  for (int i = 0; i < model.n(); ++i) out.emplace_back(f(model.spec[i]));
  return out;
}

template <class F>
VecX per_joint(const Model& model, F&& f) {
  VecX out(model.n());
  for (int i = 0; i < model.n(); ++i) out[i] = f(model.spec[i]);
  return out;
}

}  // namespace

void bind_model(py::module_& m) {
  py::class_<PyModel, std::shared_ptr<PyModel>> cls(m, "Model", R"doc(
A tree of rigid bodies joined by 1-DoF revolute or prismatic joints (parents before children).

Body frames sit at each body's centre of mass with the joint frame's orientation (docs/paper.md C-3);
``joint_placements`` gives the joint frames (Pinocchio's ``oMi``). Twists are ordered
(angular, linear) as in the paper. Build one with ``Model.from_urdf``, ``hovi.models``, or
``Model()`` followed by ``add_body``.
)doc");
  cls.def(py::init([]() { return std::make_shared<PyModel>(); }), "An empty model (add bodies with add_body).")
      .def_static(
          "from_urdf",
          [](const PathOrXml& source, const std::string& base, bool expand_joints, const ArrayLike& planar_normal) {
            UrdfOptions opt;
            opt.base = parse_base(base);
            opt.expand_joints = expand_joints;
            opt.planar_normal = as_vector(planar_normal, "planar_normal", 3);
            const std::string src = py::str(py::module_::import("os").attr("fspath")(source));
            auto pm = std::make_shared<PyModel>();
            std::vector<std::string> warnings;
            pm->model = model_from_urdf(src, opt, &warnings);
            for (const std::string& w : warnings)  // an error if warnings are errors (python -W error)
              if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) < 0) throw py::error_already_set();
            return pm;
          },
          py::arg("source"), py::arg("base") = "fixed", py::arg("expand_joints") = false,
          py::arg("planar_normal") = py::make_tuple(0.0, 1.0, 0.0), R"doc(
Load a URDF file (source: a path) or XML string (source: the text); returns a Model.

base: 'fixed' (root link welded to the world), 'floating' (the free joint, as Pinocchio's free
flyer: q = (x, y, z, qx, qy, qz, qw, joints...), nq = n + 1, the base's velocity (linear, angular) in
its own frame; integrated on the group, no singular attitude), 'euler' (6 joints x, y, z, yaw, pitch,
roll: Z-Y-X Euler angles, singular at pitch = ±pi/2; the paper's robots) or 'planar' (2 prismatic + 1
revolute about planar_normal (3,), default the x-z plane). expand_joints: expand URDF floating/planar joints the
same way instead of raising. Fixed joints are merged (inertia lumped into the parent);
continuous joints become revolute joints without limits; mimic joints are kept as metadata
(integrated as independent joints). Raises hovi.URDFError naming the link or joint at fault. A link
whose rotational inertia violates the triangle inequality (no rigid body has it; add_body refuses it)
is loaded as given with a UserWarning naming the link (URDF files in use carry such inertias).
)doc")
      .def(
          "add_body",
          [](PyModel& self, const std::string& name, const OptIndex& parent, const std::string& joint_type,
             const ArrayLike& axis, const OptArrayLike& placement, double mass, const ArrayLike& com,
             const ArrayLike& inertia, const std::string& joint_name, double lower, double upper) {
            BodySpec s;
            s.name = name;
            s.joint_name = joint_name.empty() ? name + "_joint" : joint_name;
            if (parent.is_none()) s.parent = -1;
            else if (py::isinstance<py::str>(parent)) {
              s.parent = self.model.body_index(parent.cast<std::string>());
              if (s.parent < 0) throw ModelError("add_body('" + name + "'): no body named '" + parent.cast<std::string>() + "'");
            } else s.parent = parent.cast<int>();
            s.mass = mass;
            s.com = as_vector(com, "com", 3);
            s.inertia = as_matrix(inertia, "inertia", 3, 3);
            if (joint_type == "free") {  // x, y, z sliders and yaw, pitch, roll in a chart of SO(3)
              if (s.parent != -1 || self.model.n() != 0 || !placement.is_none())
                throw ModelError("add_body('" + name + "'): a free joint must be the model's first body, on the world "
                                 "(parent None, no placement)");
              s.type = JointType::Revolute;
              s.axis = Vec3::UnitX();
              Model().add_body(s);  // the body's own checks (mass, inertia) before the model changes
              const char* suffix[] = {"_x", "_y", "_z", "_rz", "_ry"};
              const Vec3 axes[] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitY()};
              for (int k = 0; k < 5; ++k) {
                BodySpec b;
                b.name = name + suffix[k];
                b.joint_name = s.joint_name + suffix[k];
                b.parent = k - 1;
                b.type = k < 3 ? JointType::Prismatic : JointType::Revolute;
                b.axis = axes[k];
                self.model.add_body(b);
              }
              s.joint_name += "_rx";
              s.parent = 4;
              const int i = self.model.add_body(s);
              self.model.set_rotation_chart(3);
              self.changed("add_body");
              return i;
            }
            s.type = parse_type(joint_type);
            s.axis = as_vector(axis, "axis", 3);
            if (!placement.is_none()) s.placement = as_se3(placement, "placement");
            s.limits.lower = lower;
            s.limits.upper = upper;
            const int i = self.model.add_body(s);
            self.changed("add_body");
            return i;
          },
          py::arg("name"), py::arg("parent"), py::arg("joint_type") = "revolute", py::arg("axis") = py::make_tuple(0.0, 0.0, 1.0),
          py::arg("placement") = py::none(), py::arg("mass") = 0.0, py::arg("com") = py::make_tuple(0.0, 0.0, 0.0),
          py::arg("inertia") = py::array_t<double>(std::vector<py::ssize_t>{3, 3}, std::vector<double>(9, 0.0).data()),
          py::arg("joint_name") = "", py::arg("lower") = -std::numeric_limits<double>::infinity(),
          py::arg("upper") = std::numeric_limits<double>::infinity(), R"doc(
Append a body; returns its index. parent: index or body name, None for the world. joint_type:
'revolute', 'prismatic' or 'free' (the first body only: the free joint, as URDF base='floating' gives;
six joints, the body the last, q as Pinocchio's free flyer).
placement: (4, 4) pose of the joint frame in the parent's joint frame at q = 0 (default identity).
axis: (3,) joint axis in the joint frame. com: (3,) centre of mass in the joint frame. inertia:
(3, 3) rotational inertia about the COM (joint-frame axes): symmetric, no negative principal moment, and
none above the sum of the other two (the triangle inequality, e.g. izz <= ixx + iyy). lower, upper: joint
position limits. Raises hovi.ModelError naming the body on invalid input.
)doc")
      .def("copy", &copy_of, "An independent copy (later changes to either do not affect the other).")
      .def("__copy__", &copy_of, "The same as copy().")
      .def("__deepcopy__", [](const PyModel& s, const py::object&) { return copy_of(s); }, py::arg("memo"),
           "The same as copy().")
      .def(py::pickle([](const PyModel& s) { return py::bytes(serialize(s.model)); },
                      [](const py::bytes& state) {
                        auto pm = std::make_shared<PyModel>();
                        pm->model = deserialize(state);
                        return pm;
                      }))
      .def_property_readonly("n", [](const PyModel& s) { return s.model.n(); }, "Number of joints = DoF = bodies.")
      .def_property_readonly("nv", [](const PyModel& s) { return s.model.n(); },
                             "The velocity's size: the degrees of freedom, n.")
      .def_property_readonly("nq", [](const PyModel& s) { return s.model.nq(); },
                             "The configuration's size: n, or n + 1 with a free base (its attitude a quaternion).")
      .def_property_readonly("free_base", [](const PyModel& s) { return s.model.rotation_chart >= 0; },
                             "True if joints 0-5 are the free joint (URDF base='floating'): q as Pinocchio's free flyer.")
      .def("neutral", [](const PyModel& s) {
            VecX q = VecX::Zero(s.model.nq());
            if (s.model.rotation_chart >= 0) q[6] = 1;  // the identity quaternion (0, 0, 0, 1)
            return q;
          }, "The zero configuration (nq,): the joints at 0, a free base at the origin with the identity attitude.")
      .def("integrate", [](const PyModel& s, const ArrayLike& q, const ArrayLike& v) {
            const VecX qv = as_vector(q, "q", s.model.nq()), vv = as_vector(v, "v", s.model.n());
            if (s.model.rotation_chart < 0) return VecX(qv + vv);
            return FreeBase(s.model).integrate(qv, vv);
          }, py::arg("q"), py::arg("v"),
          "q ⊕ v (nq,): the configuration reached from q (nq,) along the velocity v (n,) in unit time; a free "
          "base moves along its body twist (Pinocchio's integrate), the other joints by q + v.")
      .def("difference", [](const PyModel& s, const ArrayLike& q0, const ArrayLike& q1) {
            const VecX a = as_vector(q0, "q0", s.model.nq()), b = as_vector(q1, "q1", s.model.nq());
            if (s.model.rotation_chart < 0) return VecX(b - a);
            return FreeBase(s.model).difference(a, b);
          }, py::arg("q0"), py::arg("q1"),
          "q1 ⊖ q0 (n,): the velocity v with integrate(q0, v) = q1 (Pinocchio's difference; a free base by the "
          "logarithm of SE(3)).")
      .def_property_readonly("total_mass", [](const PyModel& s) { return s.model.total_mass(); }, "Sum of the body masses (kg).")
      .def_property(
          "gravity", [](const PyModel& s) { return Vec3(s.model.gravity); },
          [](PyModel& s, const ArrayLike& g) {
            s.model.gravity = as_vector(g, "gravity", 3);
            s.changed("gravity");
          },
          "Gravity in the world frame (default (0, 0, -9.81)).")
      .def_property_readonly("body_names", [](const PyModel& s) { return per_body(s.model, [](const BodySpec& b) { return b.name; }); },
                             "(n,) list of the body (link) names, body i moved by joint i.")
      .def_property_readonly("joint_names", [](const PyModel& s) { return per_body(s.model, [](const BodySpec& b) { return b.joint_name; }); },
                             "(n,) list of the joint names.")
      .def_property_readonly("joint_types", [](const PyModel& s) { return per_body(s.model, [](const BodySpec& b) { return type_name(b.type); }); },
                             "(n,) list of the joint types, 'revolute' or 'prismatic'.")
      .def_property_readonly("parents", [](const PyModel& s) { return s.model.parent; }, "(n,) list of the parent body index per body, -1 for the world.")
      .def_property_readonly("masses", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.mass; }); },
                             "(n,) body masses (kg).")
      .def_property_readonly("lower_limits", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.limits.lower; }); },
                             "(n,) lower joint position limits (URDF <limit>; -inf where none).")
      .def_property_readonly("upper_limits", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.limits.upper; }); },
                             "(n,) upper joint position limits (URDF <limit>; inf where none).")
      .def_property_readonly("velocity_limits", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.limits.velocity; }); },
                             "(n,) joint velocity limits (URDF metadata; inf where none).")
      .def_property_readonly("effort_limits", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.limits.effort; }); },
                             "(n,) joint effort limits (URDF metadata, the default control bounds of trajopt; inf where none).")
      .def_property_readonly("damping", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.damping; }); }, "(n,) URDF <dynamics damping> per joint (metadata; see add_damper for a damper).")
      .def_property_readonly("friction", [](const PyModel& s) { return per_joint(s.model, [](const BodySpec& b) { return b.friction; }); }, "(n,) URDF <dynamics friction> per joint (metadata).")
      .def_property_readonly("mimic", [](const PyModel& s) {
            py::typing::Dict<py::str, Tuple<std::string, double, double>> d;
            for (const BodySpec& b : s.model.spec)
              if (b.mimic) d[py::str(b.joint_name)] = py::make_tuple(b.mimic->joint, b.mimic->multiplier, b.mimic->offset);
            return d;
          }, "{joint: (leader, multiplier, offset)} for URDF mimic joints (metadata only).")
      .def_property_readonly("visuals", [](const PyModel& s) {
            py::typing::List<StrDict> out;
            for (const Visual& v : s.model.visuals) out.append(visual_dict(v));
            return out;
          }, R"doc(
(V,) list of the visual shapes (URDF ``<visual>``, or add_visual), metadata for viewers, as dicts
with body (index, -1 = the world), link, shape ('box', 'cylinder', 'sphere', 'mesh'), size (3,)
(box: x, y, z; cylinder: radius, length, 0 along z; sphere: radius, 0, 0), filename (meshes:
package://..., or absolute), scale (3,), origin (4, 4) (the shape in the body's joint frame,
see joint_placements) and rgba ((4,) or None).
)doc")
      .def("add_visual", [](PyModel& s, const OptIndex& body, const std::string& shape, const OptArrayLike& size,
                            const OptArrayLike& origin, const OptArrayLike& rgba, const std::string& filename,
                            const ArrayLike& scale, const std::string& link) {
            s.model.add_visual(make_visual(s.model, body, shape, size, origin, rgba, filename, scale, link));
          }, py::arg("body"), py::arg("shape"), py::arg("size") = py::none(), py::arg("origin") = py::none(),
          py::arg("rgba") = py::none(), py::arg("filename") = "", py::arg("scale") = py::make_tuple(1.0, 1.0, 1.0),
          py::arg("link") = "", R"doc(
Attach a visual shape to a body (index or name; None = the world). shape: 'box' (size: x, y, z),
'cylinder' (size: radius, length; axis z), 'sphere' (size: radius) or 'mesh' (filename, scale).
origin: (4, 4) pose in the body's joint frame (default identity); rgba: (4,) in [0, 1].
Metadata only: the dynamics and existing integrators are unaffected. Raises ModelError on bad input.
)doc")
            .def("add_spring", [](PyModel& s, const Index& joint, double k, double rest) {

            s.model.add_spring(joint_arg(s.model, joint), k, rest);
            s.changed("add_spring");
          }, py::arg("joint"), py::arg("stiffness"), py::arg("rest") = 0.0,
          "Linear joint spring Q = -stiffness (q - rest) on a joint (index or name); adds 1/2 k (q - rest)^2 to V. "
          "stiffness and rest finite (a negative stiffness is allowed: still conservative); ModelError otherwise.")
      .def("add_damper", [](PyModel& s, const Index& joint, double c) {
            s.model.add_damper(joint_arg(s.model, joint), c);
            s.changed("add_damper");
          }, py::arg("joint"), py::arg("damping"), "Linear joint damper Q = -damping q̇ on a joint (index or name); ModelError naming the joint unless "
          "damping is finite and non-negative.")
      .def("add_actuator", [](PyModel& s, const Index& joint, double gear) {
            const int k = s.model.add_actuator(joint_arg(s.model, joint), gear);
            s.changed("add_actuator");
            return k;
          }, py::arg("joint"), py::arg("gear") = 1.0,
          "A new control input u[k] acting on the joint as Q += gear u[k]; returns k.")
      .def("add_control", [](PyModel& s) {
            const int k = s.model.add_control();
            s.changed("add_control");
            return k;
          },
           "A new control input with no joint actuation (for control-scaled wrenches); returns its index.")
      .def("add_point_wrench", [](PyModel& s, const Index& body, const ArrayLike& force, const ArrayLike& torque,
                                  const OptArrayLike& point, const std::string& frame, const OptInt& control) {
            const int i = body_arg(s.model, body);
            const Vec3 r = point.is_none() ? Vec3::Zero() : s.model.point_in_com_frame(i, as_vector(point, "point", 3));
            PointWrench::Frame f;
            if (frame == "world") f = PointWrench::Frame::World;
            else if (frame == "body") f = PointWrench::Frame::Body;
            else throw InputError("frame must be 'world' or 'body', got '" + frame + "'");
            const int c = control.is_none() ? -1 : control.cast<int>();
            if (control.is_none() == false && c < 0) throw ModelError("add_point_wrench: control index must be >= 0");
            s.model.add_wrench(std::make_shared<PointWrench>(i, r, as_vector(force, "force", 3), as_vector(torque, "torque", 3), f, c));
            s.changed("add_point_wrench");
          }, py::arg("body"), py::arg("force") = py::make_tuple(0.0, 0.0, 0.0), py::arg("torque") = py::make_tuple(0.0, 0.0, 0.0),
          py::arg("point") = py::none(), py::arg("frame") = "world", py::arg("control") = py::none(), R"doc(
A force (3,) (and torque (3,)) on a body (index or name), applied at `point` (3,) (in the body's
joint frame; default: its centre of mass). frame='world': components fixed in the world; frame='body': components turn with the
body (a follower force). control=k scales the wrench by the control input u[k].
)doc")
      .def("add_drag", [](PyModel& s, const Index& body, double linear, double angular) {
            const int i = body_arg(s.model, body);
            if (!(std::isfinite(linear) && linear >= 0 && std::isfinite(angular) && angular >= 0)) {
              std::ostringstream os;  // a negative coefficient would feed energy in
              os << "add_drag: body '" << s.model.spec[i].name << "': linear and angular must be finite and "
                 << "non-negative, got linear " << linear << ", angular " << angular;
              throw ModelError(os.str());
            }
            s.model.add_wrench(std::make_shared<BodyDrag>(i, linear, angular));
            s.changed("add_drag");
          }, py::arg("body"), py::arg("linear"), py::arg("angular") = 0.0,
          "Linear drag on a body (index or name) at its centre of mass, in the body frame: F = -(angular w, linear v_com); "
          "ModelError unless both coefficients are finite and non-negative.")
      .def("add_point_constraint", [](PyModel& s, const Index& body, const OptArrayLike& point,
                                      const OptArrayLike& target, const std::string& axes) {
            if (target.is_none()) throw InputError("add_point_constraint: target (a world point, (3,)) is required");
            const int i = body_arg(s.model, body);
            const Vec3 r = point.is_none() ? Vec3::Zero() : s.model.point_in_com_frame(i, as_vector(point, "point", 3));
            s.model.add_constraint(std::make_shared<PointConstraint>(i, r, as_vector(target, "target", 3), axes));
            s.changed("add_point_constraint");
          }, py::arg("body"), py::arg("point") = py::none(), py::arg("target") = py::none(), py::arg("axes") = "xyz", R"doc(
Hold a point (3,) of a body (in its joint frame; default the centre of mass) at a world point target (3,):
h = P (x(q) - target) with P the rows of `axes` ('xyz', or e.g. 'xz' for planar use).
)doc")
      .def("add_loop_constraint", [](PyModel& s, const Index& b1, const ArrayLike& p1, const Index& b2,
                                     const ArrayLike& p2, const std::string& axes) {
            const int i = body_arg(s.model, b1), j = body_arg(s.model, b2);
            const Vec3 r1 = s.model.point_in_com_frame(i, as_vector(p1, "point1", 3)),
                       r2 = s.model.point_in_com_frame(j, as_vector(p2, "point2", 3));
            s.model.add_constraint(std::make_shared<LoopConstraint>(i, r1, j, r2, axes));
            s.changed("add_loop_constraint");
          }, py::arg("body1"), py::arg("point1"), py::arg("body2"), py::arg("point2"), py::arg("axes") = "xyz",
          "Make point1 (3,) of body1 and point2 (3,) of body2 (each in its body's joint frame) coincide: a loop closure (the rows of `axes`).")
      .def("add_orientation_constraint", [](PyModel& s, const Index& body, const ArrayLike& R0) {
            s.model.add_constraint(std::make_shared<OrientationConstraint>(body_arg(s.model, body), as_matrix(R0, "rotation", 3, 3)));
            s.changed("add_orientation_constraint");
          }, py::arg("body"), py::arg("rotation"), "Hold a body's orientation at the world rotation `rotation` (3, 3) (3 equations).")
      .def("add_joint_coupling", [](PyModel& s, const ArrayLike& c, double offset) {
            s.model.add_constraint(std::make_shared<JointCoupling>(as_vector(c, "coefficients", s.model.n()), offset));
            s.changed("add_joint_coupling");
          }, py::arg("coefficients"), py::arg("offset") = 0.0, "A linear coupling of joint coordinates: coefficients (n,) . q = offset (1 equation).")
      .def_property_readonly("n_constraints", [](const PyModel& s) { return s.model.n_constraints(); },
                             "Number of constraint equations.")
      .def("constraint_values", [](PyModel& s, const ArrayLike& q) {
            const VecX qv = s.config(q);
            forward_kinematics(s.model, s.ws(), qv);
            VecX h(s.model.n_constraints());
            constraint_values(s.model, KinematicsView{s.model, s.ws().g.data(), s.ws().Sbar.data(), 1}, qv, h);
            return h;
          }, py::arg("q"), "q: (nq,); returns h(q), (n_constraints,), of all constraints stacked.")
      .def("constraint_jacobian", [](PyModel& s, const ArrayLike& q) {
            const VecX qv = s.config(q);
            forward_kinematics(s.model, s.ws(), qv);
            MatX J(s.model.n_constraints(), s.model.n());
            constraint_jacobian(s.model, KinematicsView{s.model, s.ws().g.data(), s.ws().Sbar.data(), 1}, J);
            if (s.model.rotation_chart >= 0) J = J * s.velocity_map(qv);
            return J;
          }, py::arg("q"), "q: (nq,); returns Dh(q), (n_constraints, n) (a free base: in its velocity's coordinates).")
      .def_property_readonly("n_controls", [](const PyModel& s) { return s.model.n_controls(); },
                             "Number m of control inputs (add_actuator, add_control).")
      .def_property_readonly("actuation", [](const PyModel& s) { return MatX(s.model.joint_forces.actuation); },
                             "(n, m) actuation map B: joint forces Q += B u.")
      .def_property_readonly("stiffness", [](const PyModel& s) { return VecX(s.model.joint_forces.stiffness); },
                             "(n,) joint spring stiffness per joint (the sum of its add_spring springs; 0 where none).")
      .def_property_readonly("joint_damping", [](const PyModel& s) { return VecX(s.model.joint_forces.damping); },
                             "(n,) joint damper coefficient per joint (add_damper; 0 where none).")
      .def("scale_mass", [](PyModel& s, const Index& body, const Real& factor) {
            s.model.scale_mass(body_arg(s.model, body), real_arg(factor, "scale_mass: factor"));
            s.changed("scale_mass");
          }, py::arg("body"), py::arg("factor"), R"doc(
Multiply a body's (index or name) mass and rotational inertia by factor > 0 (its density; shape and
centre of mass kept): a plant that differs from the model a controller was made on
(``model.copy()`` first). Raises hovi.ModelError for an unknown body or a factor outside
[1e-12, 1e12], and ValueError for a factor that is not a number.
)doc")
      .def("set_armature", [](PyModel& s, const Index& joint, double value) {
            s.model.set_armature(joint_arg(s.model, joint), value);
            s.changed("set_armature");
          }, py::arg("joint"), py::arg("armature"), R"doc(
Joint armature (rotor inertia reflected through the transmission, Pinocchio's model.armature,
MuJoCo's joint armature) on a joint (index or name): adds 1/2 armature q̇_joint^2 to the kinetic
energy, i.e. armature to the joint's diagonal entry of the mass matrix. Replaces the joint's
previous value. Raises hovi.ModelError unless armature is finite and non-negative.
)doc")
      .def_property(
          "armature", [](const PyModel& s) { return VecX(s.model.armature); },
          [](PyModel& s, const ArrayLike& a) {
            const VecX value = s.vec(a, "armature");
            const VecX old = s.model.armature;
            try {
              for (int i = 0; i < s.model.n(); ++i) s.model.set_armature(i, value[i]);
            } catch (...) {
              s.model.armature = old;  // all or nothing
              throw;
            }
            s.changed("armature");
          },
          "(n,) joint armature per joint (see set_armature; 0 where none). Set it whole with an (n,) array of finite, non-negative values.")
      .def_property_readonly("n_wrenches", [](const PyModel& s) { return s.model.wrenches.size(); },
                             "Number of body wrench elements (add_point_wrench, add_drag).")
      .def("body_index", [](const PyModel& s, const std::string& name) {
            const int i = s.model.body_index(name);
            if (i < 0) throw py::key_error("no body named '" + name + "'");
            return i;
          }, py::arg("name"), "Index of the body (link) called `name`; KeyError if there is none.")
      .def("joint_index", [](const PyModel& s, const std::string& name) {
            const int i = s.model.joint_index(name);
            if (i < 0) throw py::key_error("no joint named '" + name + "'");
            return i;
          }, py::arg("name"), "Index of the joint called `name`; KeyError if there is none.")
      .def("summary", [](const PyModel& s) { return summary(s.model); }, "A table of bodies and joints.")
      .def("__repr__", [](const PyModel& s) {
            std::ostringstream os;
            os << "<hovi.Model: " << s.model.n() << " DoF, mass " << s.model.total_mass() << " kg>";
            return os.str();
          })
      .def("body_poses", [](PyModel& s, const ArrayLike& q) {
            forward_kinematics(s.model, s.ws(), s.config(q));
            std::vector<Mat4> out;
            for (const SE3& g : s.ws().g) out.push_back(g.matrix());
            return stack(out);
          }, py::arg("q"), "q: (n,) joint positions; returns (n, 4, 4) world poses g_i of the body frames (at each centre of mass).")
      .def("joint_placements", [](PyModel& s, const ArrayLike& q) {
            forward_kinematics(s.model, s.ws(), s.config(q));
            std::vector<Mat4> out;
            for (int i = 0; i < s.model.n(); ++i) out.push_back(joint_placement(s.model, s.ws(), i).matrix());
            return stack(out);
          }, py::arg("q"), "q: (n,) joint positions; returns (n, 4, 4) world poses of the joint frames (Pinocchio's oMi).")
      .def("spatial_twists", [](PyModel& s, const ArrayLike& q) {
            forward_kinematics(s.model, s.ws(), s.config(q));
            return stack(s.ws().Sbar);
          }, py::arg("q"), "q: (n,) joint positions; returns (n, 6) spatial joint twists S̄_i = Ad_{g_i} S_i, (angular, linear).")
      .def("spatial_velocities", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd) {
            const VecX qc = s.config(q);
            forward_kinematics(s.model, s.ws(), qc, s.velocity(qc, qd, "qdot"));
            return stack(s.ws().v);
          }, py::arg("q"), py::arg("qdot"), "q, qdot: (n,); returns (n, 6) spatial velocities v̄_i = (ġ g^{-1})^∨, (angular, linear).")
      .def("kinetic_energy", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd) {
            const VecX qc = s.config(q);
            return kinetic_energy(s.model, s.ws(), qc, s.velocity(qc, qd, "qdot"));
          }, py::arg("q"), py::arg("qdot"), "Kinetic energy K = 1/2 q̇^T M(q) q̇ (joint armature included); q, qdot: (n,); returns a float.")
      .def("potential_energy", [](PyModel& s, const ArrayLike& q) {
            return potential_energy(s.model, s.ws(), s.config(q));
          }, py::arg("q"), "q: (n,); the gravitational potential -sum m_i g^T p_i (p_i the centre of mass) plus the springs' 1/2 k (q - rest)^2.")
      .def("energy", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd) {
            const VecX qv = s.config(q);
            return kinetic_energy(s.model, s.ws(), qv, s.velocity(qv, qd, "qdot")) + potential_energy(s.model, s.ws(), qv);
          }, py::arg("q"), py::arg("qdot"), "Total mechanical energy K + V; q, qdot: (n,); returns a float.")
      .def("mass_matrix", [](PyModel& s, const ArrayLike& q) {
            const VecX qc = s.config(q);
            const MatX M = mass_matrix(s.model, s.ws(), qc);
            if (s.model.rotation_chart < 0) return M;
            const MatX T = s.velocity_map(qc);
            return MatX(T.transpose() * M * T);
          }, py::arg("q"), "q: (nq,); returns the joint-space mass matrix M(q), (n, n), the joint armature on its diagonal (a free base: in its velocity's coordinates).")
      .def("forward_dynamics", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd, const OptArrayLike& tau) {
            const VecX t = tau.is_none() ? VecX::Zero(s.model.n()) : s.vec(tau, "tau");
            const VecX qc = s.config(q);
            if (s.model.rotation_chart < 0) return VecX(forward_dynamics(s.model, s.ws(), qc, s.vec(qd, "qdot"), t));
            // a = T^-1 (q̈ - Ṫ v) with q̈ = FD(q, T v, T^-T tau)
            const MatX T = s.velocity_map(qc);
            const VecX v = s.vec(qd, "qdot");
            const FreeBase base(s.model);
            const VecX qdd = forward_dynamics(s.model, s.ws(), qc, T * v, T.transpose().lu().solve(t));
            return VecX(T.lu().solve(qdd - base.velocity_rate(qc, s.attitude, v)));
          }, py::arg("q"), py::arg("qdot"), py::arg("tau") = py::none(),
          "q, qdot, tau: (n,) (tau default zero); returns q̈ = FD(q, q̇, tau), (n,), by the articulated-body algorithm (O(n)), gravity and the model's forces included.")
      .def("kinetic_energy_hessians", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd) {
            s.chart_coordinates_only("kinetic_energy_hessians");
            kinetic_hessians(s.model, s.ws(), s.vec(q, "q"), s.vec(qd, "qdot"));
            const Data& d = s.ws();
            return py::make_tuple(d.Kvv, d.Kvq, d.Kqv, d.Kqq);
          }, py::arg("q"), py::arg("qdot"), R"doc(
Algorithm 2, O(n^2). q, qdot: (n,); returns (Kvv, Kvq, Kqv, Kqq), each (n, n), with Kvv = d2K/dq̇2, Kvq[i, j] = d/dq_j (dK/dq̇_i),
Kqv[i, j] = d/dq̇_j (dK/dq_i) = Kvq.T, Kqq = d2K/dq2.
)doc")
      .def("gravity_hessian", [](PyModel& s, const ArrayLike& q) {
            s.chart_coordinates_only("gravity_hessian");
            return MatX(gravity_hessian(s.model, s.ws(), s.vec(q, "q")));
          }, py::arg("q"), "Algorithm 3, O(n^2). q: (n,); returns d2V_g/dq2 (n, n) of the gravitational potential (springs not included).")
      .def("force_jacobians", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd, const OptArrayLike& u) {
            const VecX uu = u.is_none() ? VecX::Zero(s.model.n_controls()) : as_vector(u, "u", s.model.n_controls());
            const VecX qc = s.config(q);
            ForceJacobians fj(s.model);
            if (s.model.rotation_chart < 0) {
              force_jacobians(s.model, s.ws(), qc, s.vec(qd, "qdot"), uu, fj);
              return py::make_tuple(VecX(fj.Q), MatX(fj.Qq), MatX(fj.Qv), MatX(fj.Qu));
            }
            // a free base: Q_v = T^T Q(q, T v, u) in the velocity's coordinates, by a tangent δ of q
            const VecX v = s.vec(qd, "qdot");
            MatX dq, dTv, dTf;
            force_jacobians(s.model, s.ws(), qc, s.velocity(qc, qd, "qdot"), uu, fj);
            FreeBase(s.model).tangent_maps(s.attitude, v, fj.Q, dq, dTv, dTf);
            const MatX& T = dq;  // the velocity map at θ = 0
            return py::make_tuple(VecX(T.transpose() * fj.Q), MatX(dTf + T.transpose() * (fj.Qq * dq + fj.Qv * dTv)),
                                  MatX(T.transpose() * fj.Qv * T), MatX(T.transpose() * fj.Qu));
          }, py::arg("q"), py::arg("qdot"), py::arg("u") = py::none(), R"doc(
q: (nq,), qdot: (n,), u: (m,) (default zero); returns (Q (n,), dQ/dq (n, n), dQ/dq̇ (n, n), dQ/du (n, m))
of the generalized non-conservative force: joint springs, dampers and actuators plus the body wrench
elements mapped to joint space (gravity not included). A free base: in its velocity's coordinates,
dQ/dq by a tangent δ of q (q ⊕ δ).
)doc")
      .def("inverse_dynamics", [](PyModel& s, const ArrayLike& q, const ArrayLike& qd, const ArrayLike& qdd) {
            const VecX qc = s.config(q);
            if (s.model.rotation_chart < 0)
              return VecX(inverse_dynamics(s.model, s.ws(), qc, s.vec(qd, "qdot"), s.vec(qdd, "qddot")));
            // tau = T^T ID(q, T v, T a + Ṫ v)
            const MatX T = s.velocity_map(qc);
            const VecX v = s.vec(qd, "qdot");
            const VecX a = T * s.vec(qdd, "qddot") + FreeBase(s.model).velocity_rate(qc, s.attitude, v);
            return VecX(T.transpose() * inverse_dynamics(s.model, s.ws(), qc, T * v, a));
          }, py::arg("q"), py::arg("qdot"), py::arg("qddot"),
          "q, qdot, qddot: (n,); returns tau = M(q) q̈ + C(q, q̇) q̇ + G(q), (n,), by recursive Newton-Euler (O(n)).");

  m.def("pendulum", [](int n, double length, double mass, double radius) {
        auto pm = std::make_shared<PyModel>();
        pm->model = models::pendulum(n, length, mass, radius);
        return pm;
      }, py::arg("n"), py::arg("length") = 0.5, py::arg("mass") = 1.0, py::arg("radius") = 0.02,
      "The paper's n-link 3D pendulum (see hovi.models.pendulum).");

  m.def("body_point_kinematics", [](PyModel& pm, const ArrayLike& Q, const std::vector<int>& bodies,
                                    const ArrayLike& points) {
        const MatX q_in = as_matrix(Q, "q", -1, pm.model.nq());
        MatX r = as_matrix(points, "points", static_cast<long>(bodies.size()), 3).transpose();
        for (int i = 0; i < r.cols(); ++i) {  // joint frame -> COM frame
          if (bodies[i] < 0 || bodies[i] >= pm.model.n())
            throw ModelError("body index " + std::to_string(bodies[i]) + " out of range");
          r.col(i) = pm.model.point_in_com_frame(bodies[i], r.col(i));
        }
        MatX X, J;  // the GIL stays held: pm.ws() is the model's one shared workspace
        const int n = pm.model.n(), P = static_cast<int>(q_in.rows()), m = static_cast<int>(r.cols());
        if (pm.model.rotation_chart < 0) {
          body_point_kinematics(pm.model, pm.ws(), q_in.transpose(), bodies, r, X, &J);
        } else {  // a free base: each configuration in its own chart, the Jacobians in its velocity (J T)
          X.resize(3, P * m);
          J.resize(3, P * m * n);
          MatX Xp, Jp;
          for (int p = 0; p < P; ++p) {
            const VecX qc = pm.config(py::cast(VecX(q_in.row(p).transpose())));
            body_point_kinematics(pm.model, pm.ws(), qc, bodies, r, Xp, &Jp);
            const MatX T = pm.velocity_map(qc);
            X.middleCols(p * m, m) = Xp;
            for (int i = 0; i < m; ++i) J.middleCols((p * m + i) * n, n) = Jp.middleCols(i * n, n) * T;
          }
        }
        py::array_t<double> Xs(std::vector<py::ssize_t>{P, m, 3}), Js(std::vector<py::ssize_t>{P, m, 3, n});
        auto x = Xs.mutable_unchecked<3>();
        auto j = Js.mutable_unchecked<4>();
        for (int p = 0; p < P; ++p)
          for (int i = 0; i < m; ++i)
            for (int a = 0; a < 3; ++a) {
              x(p, i, a) = X(a, p * m + i);
              for (int k = 0; k < n; ++k) j(p, i, a, k) = J(a, (p * m + i) * n + k);
            }
        return py::make_tuple(Xs, Js);
      }, py::arg("model"), py::arg("q"), py::arg("bodies"), py::arg("points"), R"doc(
World positions (P, m, 3) and Jacobians (P, m, 3, n) of m body points at P configurations q (P, nq)
(a free base: the Jacobians in its velocity, v):
point i is points[i] (in the body's joint frame, as for add_point_constraint) of body bodies[i].
One forward kinematics per configuration serves all the points.
)doc");
}

}  // namespace hovi::py_bind
