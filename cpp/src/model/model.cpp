#include "hovi/model/model.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <sstream>

#include "hovi/model/constraint.hpp"
#include "hovi/errors.hpp"

namespace hovi {
namespace {

std::string describe(const BodySpec& s) {
  return "body '" + s.name + "' (joint '" + s.joint_name + "')";
}

template <class D>
bool finite(const Eigen::MatrixBase<D>& m) {
  return m.allFinite();
}

void validate(const BodySpec& s, int n, TriangleInequality triangle) {
  if (s.parent < -1 || s.parent >= n) {
    std::ostringstream os;
    os << describe(s) << ": parent index " << s.parent
       << " does not name an existing body (parents must be added before children)";
    throw ModelError(os.str());
  }
  if (!finite(s.com) || !finite(s.inertia) || !finite(s.placement.R) || !finite(s.placement.p) || !finite(s.axis))
    throw ModelError(describe(s) + ": non-finite value in axis, placement, centre of mass or inertia");
  if (s.axis.norm() < 1e-12) throw ModelError(describe(s) + ": joint axis has zero length");
  const Mat3 R = s.placement.R;
  if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-9 || R.determinant() < 0)
    throw ModelError(describe(s) + ": placement rotation is not a rotation matrix");
  check_inertia(describe(s), s.mass, s.inertia);
  if (triangle == TriangleInequality::Refuse) {
    const std::string violation = triangle_inequality_violation(s.inertia);
    if (!violation.empty())
      throw ModelError(describe(s) + ": rotational inertia violates the triangle inequality: " + violation +
                       " (no rigid body has such an inertia: correct it)");
  }
}

}  // namespace

std::string triangle_inequality_violation(const Mat3& inertia) {
  const Vec3 d = inertia.diagonal();
  Eigen::SelfAdjointEigenSolver<Mat3> es(inertia, Eigen::EigenvaluesOnly);
  const Vec3 l = es.eigenvalues();  // ascending
  // Relative 1e-9 with check_inertia's absolute floor of 1e-12 (entries of 1e-35 are round-off).
  const double tol = 1e-9 * l.cwiseAbs().sum() + 1e-12;
  std::ostringstream os;
  os.precision(6);
  // In any frame the diagonal obeys it too; name the entries when they show the violation.
  const char* names[] = {"ixx", "iyy", "izz"};
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3, lo = std::min(a, b), hi = std::max(a, b);
    if (d[k] > d[a] + d[b] + tol) {
      os << names[k] << " = " << d[k] << " exceeds " << names[lo] << " + " << names[hi] << " = " << d[a] + d[b];
      return os.str();
    }
  }
  if (l[2] <= l[0] + l[1] + tol) return "";
  os << "the largest principal moment " << l[2] << " exceeds the sum of the other two, " << l[0] << " + " << l[1];
  return os.str();
}

void check_inertia(const std::string& what, double mass, const Mat3& inertia) {
  if (!std::isfinite(mass) || mass < 0)
    throw ModelError(what + ": mass must be finite and non-negative, got " + std::to_string(mass));
  if (!inertia.allFinite()) throw ModelError(what + ": inertia has a non-finite entry");
  if ((inertia - inertia.transpose()).norm() > 1e-12 * (1 + inertia.norm()))
    throw ModelError(what + ": rotational inertia is not symmetric");
  if (mass == 0 && inertia.norm() == 0) return;  // a massless (virtual) body
  if (mass == 0)
    throw ModelError(what + ": non-zero rotational inertia with zero mass: give the body its mass, or zero its inertia");
  // Zero principal moments are allowed (point masses and thin rods, common in real URDFs);
  // negative ones are not.
  Eigen::SelfAdjointEigenSolver<Mat3> es(inertia);
  if (es.eigenvalues().minCoeff() < -1e-12 * std::max(1.0, es.eigenvalues().cwiseAbs().maxCoeff())) {
    std::ostringstream os;
    os << what << ": rotational inertia is not positive definite: negative principal moment (principal moments "
       << es.eigenvalues().transpose() << "): correct the inertia (a rigid body's principal moments are non-negative)";
    throw ModelError(os.str());
  }
}

void Model::add_visual(const Visual& visual) {
  check_visual(visual, n());
  visuals.push_back(visual);
}

int Model::add_body(const BodySpec& spec_in, TriangleInequality triangle) {
  validate(spec_in, n(), triangle);
  BodySpec s = spec_in;
  s.axis.normalize();
  const int i = n();
  parent.push_back(s.parent);
  children.emplace_back();
  if (s.parent >= 0) children[s.parent].push_back(i);

  // S_i = Ad_{T(c_i)}^{-1} S^J with S^J = (axis, 0) or (0, axis) in the joint frame (docs/paper.md C-3)
  Twist SJ = Twist::Zero();
  if (s.type == JointType::Revolute) SJ.head<3>() = s.axis; else SJ.tail<3>() = s.axis;
  S.push_back(Ad(SE3::Translation(-s.com), SJ));
  // g_{par,i}(0) = T(c_par)^{-1} X_i T(c_i)
  const Vec3 c_par = s.parent >= 0 ? spec[s.parent].com : Vec3::Zero();
  g_parent0.push_back(SE3::Translation(-c_par) * s.placement * SE3::Translation(s.com));
  M.push_back(SpatialInertia::AtCom(s.mass, s.inertia));
  spec.push_back(std::move(s));
  joint_forces.resize(n());
  armature.conservativeResize(n());
  armature[i] = 0;
  return i;
}

namespace {
void check_joint(const Model& m, int joint, const char* what) {
  if (joint < 0 || joint >= m.n())
    throw ModelError(std::string(what) + ": joint index " + std::to_string(joint) + " out of range (model has " +
                     std::to_string(m.n()) + " joints)");
}
// ModelError naming the call, the joint, the parameter and its value unless x is finite (and, with
// non_negative, >= 0).
void check_parameter(const Model& m, int joint, const char* what, const char* parameter, double x,
                     bool non_negative = false) {
  if (std::isfinite(x) && (!non_negative || x >= 0)) return;
  std::ostringstream os;
  os << what << ": joint '" << m.spec[joint].joint_name << "' (index " << joint << "): " << parameter
     << " must be finite" << (non_negative ? " and non-negative" : "") << ", got " << x;
  throw ModelError(os.str());
}
}  // namespace

void Model::add_spring(int joint, double stiffness, double rest) {
  check_joint(*this, joint, "add_spring");
  check_parameter(*this, joint, "add_spring", "stiffness", stiffness);
  check_parameter(*this, joint, "add_spring", "rest", rest);
  check_parameter(*this, joint, "add_spring", "stiffness * rest (the preload)", stiffness * rest);
  joint_forces.stiffness[joint] += stiffness;
  joint_forces.preload[joint] += stiffness * rest;
}

void Model::set_armature(int joint, double value) {
  check_joint(*this, joint, "set_armature");
  if (!std::isfinite(value) || value < 0)
    throw ModelError("set_armature: joint '" + spec[joint].joint_name +
                     "': armature must be finite and non-negative, got " + std::to_string(value));
  armature[joint] = value;
}

void Model::scale_mass(int body, double factor) {
  check_joint(*this, body, "scale_mass");
  // A mismatch study's plant: far beyond these bounds the mass matrix loses its scale (singular or overflowing).
  if (!(factor >= 1e-12 && factor <= 1e12)) {
    std::ostringstream os;
    os << "scale_mass: body '" << spec[body].name << "': factor must lie in [1e-12, 1e12], got " << factor;
    throw ModelError(os.str());
  }
  spec[body].mass *= factor;
  spec[body].inertia *= factor;
  M[body] = SpatialInertia::AtCom(spec[body].mass, spec[body].inertia);
}

void Model::set_rotation_chart(int j) {
  const auto refuse = [&](const std::string& why) {
    throw ModelError("set_rotation_chart: joints " + std::to_string(j) + " to " + std::to_string(j + 2) + " " + why);
  };
  if (j < 0 || j + 2 >= n()) refuse("do not exist (the model has " + std::to_string(n()) + " joints)");
  if (j != 3) refuse("must follow the free base's three sliders (j = 3)");
  for (int i = 0; i < 3; ++i)
    if (spec[i].type != JointType::Prismatic || parent[i] != i - 1 || (spec[i].axis - Vec3::Unit(i)).norm() > 1e-12 ||
        (spec[i].placement.R - Mat3::Identity()).norm() > 1e-12 || spec[i].placement.p.norm() > 1e-12)
      refuse("must follow three sliders along the world's x, y, z from its origin ('" + spec[i].joint_name +
             "' is not one)");
  for (int i = j; i <= j + 2; ++i)
    if (spec[i].type != JointType::Revolute) refuse("must be revolute ('" + spec[i].joint_name + "' is not)");
  for (int i = j; i <= j + 2; ++i)
    if (parent[i] != i - 1 || (spec[i].placement.R - Mat3::Identity()).norm() > 1e-12 || spec[i].placement.p.norm() > 1e-12)
      refuse("must be a chain without offsets ('" + spec[i].joint_name + "' is not the child of the joint before, "
             "at its origin)");
  for (int k = 0; k < 3; ++k)
    if ((spec[j + k].axis - Vec3::Unit(2 - k)).norm() > 1e-12)
      refuse("must turn about z, y and x (yaw, pitch, roll; '" + spec[j + k].joint_name + "' does not)");
  rotation_chart = j;
}

void Model::refuse_free_base(const std::string& what) const {
  if (rotation_chart >= 0)
    throw ModelError(what + " is not available for a model with a free base yet (it works in joint coordinates): "
                     "load the robot with base='euler' for it");
}

SE3 Model::chart_placement(const Mat3& centre) const {
  const Vec3 c = spec[rotation_chart].com;  // {j} is the joint frame moved to the COM: P C T(c) = g0 T(-c) C T(c)
  return g_parent0[rotation_chart] * SE3::Translation(-c) * SE3(centre, Vec3::Zero()) * SE3::Translation(c);
}

void Model::add_damper(int joint, double damping) {
  check_joint(*this, joint, "add_damper");
  check_parameter(*this, joint, "add_damper", "damping", damping, true);
  joint_forces.damping[joint] += damping;
}

int Model::add_control() {
  MatX& B = joint_forces.actuation;
  B.conservativeResize(n(), B.cols() + 1);
  B.col(B.cols() - 1).setZero();
  return static_cast<int>(B.cols()) - 1;
}

int Model::add_actuator(int joint, double gear) {
  check_joint(*this, joint, "add_actuator");
  check_parameter(*this, joint, "add_actuator", "gear", gear);
  const int k = add_control();
  joint_forces.actuation(joint, k) = gear;
  return k;
}

void Model::add_wrench(std::shared_ptr<const BodyWrench> wrench) {
  if (!wrench) throw ModelError("add_wrench: null wrench");
  if (wrench->body() < 0 || wrench->body() >= n())
    throw ModelError(std::string("add_wrench(") + wrench->kind() + "): body index " + std::to_string(wrench->body()) +
                     " out of range");
  if (wrench->max_control_index() >= n_controls())
    throw ModelError(std::string("add_wrench(") + wrench->kind() + "): control index " +
                     std::to_string(wrench->max_control_index()) + " does not exist (model has " +
                     std::to_string(n_controls()) + " controls; add them first with add_control)");
  wrenches.push_back(std::move(wrench));
}

double Model::total_mass() const {
  double m = 0;
  for (const auto& b : M) m += b.m;
  return m;
}

std::vector<int> Model::joints_moving(const std::vector<int>& bodies) const {
  std::vector<char> on_path(n(), 0);
  for (int b : bodies)
    for (int j = b; j >= 0; j = parent[j]) on_path[j] = 1;
  std::vector<int> joints;
  for (int j = 0; j < n(); ++j)
    if (on_path[j]) joints.push_back(j);
  return joints;
}

int Model::body_index(const std::string& name) const {
  for (int i = 0; i < n(); ++i)
    if (spec[i].name == name) return i;
  return -1;
}

int Model::joint_index(const std::string& name) const {
  for (int i = 0; i < n(); ++i)
    if (spec[i].joint_name == name) return i;
  return -1;
}

}  // namespace hovi

namespace hovi {

void Model::add_constraint(std::shared_ptr<const Constraint> constraint) {
  if (!constraint) throw ModelError("add_constraint: null constraint");
  constraint->check(*this);
  constraints.push_back(std::move(constraint));
}

int Model::n_constraints() const {
  int m = 0;
  for (const auto& c : constraints) m += c->dim();
  return m;
}

}  // namespace hovi
