// The immutable kinematic tree (paper Sec. 2.3): n rigid bodies, each attached to its parent
// by a one-degree-of-freedom revolute or prismatic joint, parents numbered before children.
//
// Frames follow docs/paper.md C-3: body frame {i} is the joint frame of joint i translated to the
// body's centre of mass c_i (orientation kept), so M_i = blockdiag(I_c, m 1) and p_i is the COM.
// The joint frame itself is kept for output (joint_placement) and for URDF round trips.
#pragma once
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hovi/model/body_wrench.hpp"
#include "hovi/model/joint_forces.hpp"
#include "hovi/model/visual.hpp"
#include "hovi/spatial/algebra.hpp"

namespace hovi {

class Constraint;

enum class JointType { Revolute, Prismatic };

struct JointLimits {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double velocity = std::numeric_limits<double>::infinity();
  double effort = std::numeric_limits<double>::infinity();
};

struct Mimic {          // metadata only: hovi integrates mimic joints as independent joints
  std::string joint;    // the joint this one follows
  double multiplier = 1, offset = 0;
};

// Everything the user specifies for one body; Model::add_body validates it.
struct BodySpec {
  std::string name;            // link name
  std::string joint_name;
  int parent = -1;             // index of the parent body, -1 for the world
  JointType type = JointType::Revolute;
  Vec3 axis = Vec3::UnitZ();   // joint axis in the joint frame (normalised on add)
  SE3 placement;               // joint frame in the parent's joint frame at q = 0
  double mass = 0;
  Vec3 com = Vec3::Zero();     // centre of mass in the joint frame
  Mat3 inertia = Mat3::Zero(); // rotational inertia about the COM, joint-frame axes
  JointLimits limits;
  std::optional<Mimic> mimic;
  double damping = 0, friction = 0;  // URDF <dynamics>, metadata
};

// Throws ModelError naming `what` unless mass >= 0 and the rotational inertia has no negative
// principal moment (zero moments allowed: point masses, thin rods); a massless body must have
// zero inertia.
void check_inertia(const std::string& what, double mass, const Mat3& inertia);

// Empty if the principal moments of the rotational inertia satisfy the triangle inequality (each at
// most the sum of the other two, as every rigid body's do: Ixx = ∫(y² + z²) dm <= Iyy + Izz; up to a
// relative 1e-9 of their sum, for round-off on thin rods and flat plates), else a sentence saying
// which moment exceeds the others (e.g. "izz = 0.3 exceeds ixx + iyy = 0.2").
std::string triangle_inequality_violation(const Mat3& inertia);

// What Model::add_body does with an inertia that violates the triangle inequality: refuse it
// (ModelError naming the body; the default), or accept it: the URDF reader accepts and warns
// (URDF files in use carry such inertias, e.g. example-robot-data's go1, b1, anymal and hyq bases),
// and a deserialised model keeps the inertias it was built with.
enum class TriangleInequality { Refuse, Accept };

class Model {
 public:
  Model() = default;
  // Appends a body; returns its index. Throws ModelError naming the body on invalid input.
  int add_body(const BodySpec& spec, TriangleInequality triangle = TriangleInequality::Refuse);

  int n() const { return static_cast<int>(parent.size()); }
  double total_mass() const;
  int body_index(const std::string& link_name) const;  // -1 if absent
  int joint_index(const std::string& joint_name) const;  // -1 if absent

  // Force elements (Assumption 1). Each throws ModelError on an unknown joint/body or bad value,
  // naming the joint and the value: every parameter finite; a damper's coefficient non-negative (a
  // negative one would feed energy in). A spring's stiffness may be negative (still conservative:
  // V = 1/2 k (q - rest)^2 with k < 0, e.g. to cancel another spring).
  void add_spring(int joint, double stiffness, double rest);  // Q -= k (q - rest)
  void add_damper(int joint, double damping);                 // Q -= c q̇, c >= 0
  int add_control();                                          // a new input u[m], no actuation yet
  int add_actuator(int joint, double gear = 1.0);             // new input u[m], Q_joint += gear u[m]
  void add_wrench(std::shared_ptr<const BodyWrench> wrench);
  int n_controls() const { return joint_forces.n_controls(); }
  void add_constraint(std::shared_ptr<const Constraint> constraint);  // checked against the model
  int n_constraints() const;                                          // equations, sum of dims
  bool has_gravity() const { return gravity.squaredNorm() > 0; }
  void add_visual(const Visual& visual);  // checked (check_visual); metadata only
  // Joint armature a_i (rotor inertia reflected through the transmission; Pinocchio's
  // model.armature, MuJoCo's joint armature): adds 1/2 a_i q̇_i^2 to the kinetic energy, so the
  // mass matrix is M(q) + diag(a). Throws ModelError unless the joint exists and value is finite
  // and non-negative.
  void set_armature(int joint, double value);
  // Multiplies a body's mass and rotational inertia by factor (its density: shape and centre of mass
  // kept), e.g. for a model-mismatch study. Throws ModelError unless the body exists and factor is
  // finite and positive.
  void scale_mass(int body, double factor);
  bool has_armature() const { return armature.size() && armature.maxCoeff() > 0; }
  // A point given in body i's joint frame, in its COM frame {i}, where the kinematics place points.
  Vec3 point_in_com_frame(int i, const Vec3& point) const { return point - spec[i].com; }
  // The joints on the paths from `bodies` (valid indices) to the root, ascending: the ones that move them.
  std::vector<int> joints_moving(const std::vector<int>& bodies) const;
  // The free base: joints 0-2 sliders along the world's x, y, z and joints 3-5 revolute about z, y, x
  // (each the child of the one before, no offsets: yaw, pitch, roll, R(θ) = Rz(θ_1) Ry(θ_2) Rx(θ_3))
  // whose rotation is a moving chart of SO(3) about a centre C that each step re-centres at the
  // body's attitude (algorithms/rotation_chart.hpp). The model's public configuration then has
  // nq = n + 1 (the three angles replaced by a unit quaternion, algorithms/free_base.hpp). j must be 3.
  // Throws ModelError unless the joints are such a chain.
  void set_rotation_chart(int j);
  int nq() const { return n() + (rotation_chart >= 0 ? 1 : 0); }
  // ModelError naming `what` for a model with a free base, where `what` works in joint coordinates only.
  void refuse_free_base(const std::string& what) const;
  // g_{par(j),j}(0) of the chart's first joint with the centre C inserted after its placement.
  SE3 chart_placement(const Mat3& centre) const;

  // Topology
  std::vector<int> parent;                 // par(i), -1 for the world {0}
  std::vector<std::vector<int>> children;  // chd(i)
  // Per body, in the COM frame {i} (paper notation)
  std::vector<Twist> S;                    // S_i, joint twist in {i}
  std::vector<SE3> g_parent0;              // g_{par(i),i}(0), {i} in {par(i)} at q_i = 0
  std::vector<SpatialInertia> M;           // M_i = blockdiag(I_c, m 1)
  // What the user gave, kept for output and metadata
  std::vector<BodySpec> spec;
  Vec3 gravity = Vec3(0, 0, -9.81);        // world frame
  JointForces joint_forces;                // springs, dampers, actuation map
  VecX armature;                           // a_i per joint, 0 where none (set_armature)
  int rotation_chart = -1;                 // the chart's first joint (set_rotation_chart), -1: none
  std::vector<std::shared_ptr<const BodyWrench>> wrenches;  // external wrenches on bodies
  std::vector<std::shared_ptr<const Constraint>> constraints;  // holonomic constraints h(q) = 0
  std::vector<Visual> visuals;             // geometry for viewers (URDF <visual>), not dynamics
};

}  // namespace hovi
