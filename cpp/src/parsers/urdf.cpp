#include "hovi/parsers/urdf.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <urdf_model/utils.h>
#include <urdf_parser/urdf_parser.h>

#include "hovi/errors.hpp"

namespace hovi {
namespace {

// Collects urdfdom's console_bridge messages so that they can go into the exception.
struct MessageCapture : console_bridge::OutputHandler {
  std::string text;
  MessageCapture() { console_bridge::useOutputHandler(this); }
  ~MessageCapture() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& msg, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) text += (text.empty() ? "" : "; ") + msg;
  }
};

// The number attributes urdfdom reads: element path below <robot>, attribute names, numbers in each,
// and whether their magnitude is bounded by kMaxMagnitude (lengths, masses, inertias, sizes: larger
// values overflow the dynamics; limits and controller gains are metadata and may be huge).
struct NumberAttributes {
  const char* path;
  const char* names;
  std::size_t count;
  bool bounded = true;
};
constexpr double kMaxMagnitude = 1e12;
const NumberAttributes kNumberAttributes[] = {
    {"link/inertial/origin", "xyz rpy", 3},
    {"link/inertial/mass", "value", 1},
    {"link/inertial/inertia", "ixx ixy ixz iyy iyz izz", 1},
    {"link/visual/origin", "xyz rpy", 3},
    {"link/visual/geometry/box", "size", 3},
    {"link/visual/geometry/cylinder", "radius length", 1},
    {"link/visual/geometry/sphere", "radius", 1},
    {"link/visual/geometry/mesh", "scale", 3},
    {"link/visual/material/color", "rgba", 4},
    {"link/collision/origin", "xyz rpy", 3},
    {"link/collision/geometry/box", "size", 3},
    {"link/collision/geometry/cylinder", "radius length", 1},
    {"link/collision/geometry/sphere", "radius", 1},
    {"link/collision/geometry/mesh", "scale", 3},
    {"joint/origin", "xyz rpy", 3},
    {"joint/axis", "xyz", 3},
    {"joint/limit", "lower upper effort velocity", 1, false},
    {"joint/dynamics", "damping friction", 1},
    {"joint/mimic", "multiplier offset", 1},
    {"joint/safety_controller", "soft_lower_limit soft_upper_limit k_position k_velocity", 1, false},
    {"joint/calibration", "rising falling", 1, false},
    {"material/color", "rgba", 4},
};

// True if `text` is `count` finite numbers as urdfdom reads them (a scalar whole, a list split at
// spaces), each at most `bound` in magnitude.
bool is_number_list(const std::string& text, std::size_t count, double bound) {
  std::vector<std::string> pieces;
  if (count == 1) pieces.push_back(text);
  else urdf::split_string(pieces, text, " ");
  std::size_t n = 0;
  for (const std::string& piece : pieces) {
    if (piece.empty()) continue;
    try {
      if (!(std::abs(urdf::strToDouble(piece.c_str())) <= bound)) return false;
    } catch (const std::runtime_error&) {
      return false;
    }
    ++n;
  }
  return n == count;
}

// Checks the number attributes of `e` (at `path`) and of its descendants; `where` names the
// enclosing link, joint or material and the elements above `e`, e.g. "link 'arm': <inertial>".
void check_element_numbers(const TiXmlElement& e, const std::string& path, const std::string& where) {
  const std::string tag = where + "<" + e.Value();
  for (const NumberAttributes& row : kNumberAttributes) {
    if (path != row.path) continue;
    std::vector<std::string> names;
    urdf::split_string(names, row.names, " ");
    for (const std::string& name : names) {
      const char* text = e.Attribute(name.c_str());
      const double bound = row.bounded ? kMaxMagnitude : std::numeric_limits<double>::max();
      if (text && !is_number_list(text, row.count, bound))
        throw UrdfError(tag + " " + name + "=\"" + text + "\">: " +
                        (row.count == 1 ? "not a finite number" : "not " + std::to_string(row.count) + " finite numbers") +
                        (row.bounded ? " of magnitude at most 1e12" : ""));
    }
  }
  for (const TiXmlElement* child = e.FirstChildElement(); child; child = child->NextSiblingElement())
    check_element_numbers(*child, path + "/" + child->Value(), tag + ">");
}

// urdfdom refuses some bad numbers but silently zeroes or drops others (a bad <inertial> leaves the
// link with zero inertia): refuse them all first, naming the element. Malformed XML is left to urdfdom.
void check_numbers(const std::string& xml) {
  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  const TiXmlElement* robot = doc.FirstChildElement("robot");
  if (doc.Error() || !robot) return;
  for (const TiXmlElement* top = robot->FirstChildElement(); top; top = top->NextSiblingElement()) {
    const char* name = top->Attribute("name");
    const std::string where = std::string(top->Value()) + " '" + (name ? name : "") + "': ";
    for (const TiXmlElement* child = top->FirstChildElement(); child; child = child->NextSiblingElement())
      check_element_numbers(*child, std::string(top->Value()) + "/" + child->Value(), where);
  }
}

SE3 to_se3(const urdf::Pose& pose) {
  const Eigen::Quaterniond quat(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  return SE3(quat.normalized().toRotationMatrix(), Vec3(pose.position.x, pose.position.y, pose.position.z));
}

Vec3 to_vec(const urdf::Vector3& v) { return Vec3(v.x, v.y, v.z); }

// The inertia of one URDF link, validated, as a SpatialInertia about the link frame; a sentence
// in `warnings` if it violates the triangle inequality.
SpatialInertia link_inertia(const urdf::Link& link, std::vector<std::string>* warnings) {
  if (!link.inertial) return SpatialInertia();
  const urdf::Inertial& in = *link.inertial;
  Mat3 Ic;
  Ic << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  check_inertia("link '" + link.name + "'", in.mass, Ic);
  const std::string violation = triangle_inequality_violation(Ic);
  if (!violation.empty() && warnings)
    warnings->push_back("link '" + link.name + "': rotational inertia violates the triangle inequality: " + violation +
                        " (no rigid body has such an inertia); loaded as given");
  const SE3 X = to_se3(in.origin);  // inertial frame in the link frame
  return SpatialInertia::AtCom(in.mass, Ic).transformed(X);
}

// A chain of 1-DoF joints standing for one multi-DoF joint.
using JointChain = std::vector<std::pair<JointType, Vec3>>;

JointChain floating_chain() {
  return {{JointType::Prismatic, Vec3::UnitX()}, {JointType::Prismatic, Vec3::UnitY()},
          {JointType::Prismatic, Vec3::UnitZ()}, {JointType::Revolute, Vec3::UnitZ()},
          {JointType::Revolute, Vec3::UnitY()},  {JointType::Revolute, Vec3::UnitX()}};
}

JointChain planar_chain(Vec3 n) {
  n.normalize();
  Vec3 t1 = Vec3::UnitX();
  for (int k = 0; k < 3; ++k)
    if (std::abs(n.dot(Vec3::Unit(k))) < 0.9) { t1 = Vec3::Unit(k); break; }
  t1 = (t1 - t1.dot(n) * n).normalized();
  return {{JointType::Prismatic, t1}, {JointType::Prismatic, t1.cross(n)}, {JointType::Revolute, n}};
}

const char* const kFloatingSuffix[] = {"_x", "_y", "_z", "_rz", "_ry", "_rx"};
const char* const kPlanarSuffix[] = {"_t1", "_t2", "_r"};

// A mesh file name as the model keeps it: package:// names stay (a viewer resolves them through
// its search path), file:// is dropped, a relative name is made absolute against the URDF's directory.
std::string mesh_path(const std::string& filename, const std::string& urdf_dir) {
  const std::string file_scheme = "file://";
  if (filename.rfind(file_scheme, 0) == 0) return filename.substr(file_scheme.size());
  if (filename.rfind("package://", 0) == 0 || filename.empty() || filename[0] == '/' || urdf_dir.empty())
    return filename;
  return urdf_dir + "/" + filename;
}

// The <visual> elements of `link` attached to `body` (-1 = world), the link frame being X in its frame.
std::vector<Visual> link_visuals(const urdf::Link& link, int body, const SE3& X, const std::string& urdf_dir) {
  std::vector<Visual> out;
  for (const urdf::VisualSharedPtr& uv : link.visual_array) {
    if (!uv || !uv->geometry) continue;
    Visual v;
    v.body = body;
    v.link = link.name;
    v.origin = X * to_se3(uv->origin);
    switch (uv->geometry->type) {
      case urdf::Geometry::BOX: {
        const auto& g = static_cast<const urdf::Box&>(*uv->geometry);
        v.shape = VisualShape::Box;
        v.size = to_vec(g.dim);
        break;
      }
      case urdf::Geometry::CYLINDER: {
        const auto& g = static_cast<const urdf::Cylinder&>(*uv->geometry);
        v.shape = VisualShape::Cylinder;
        v.size = Vec3(g.radius, g.length, 0);
        break;
      }
      case urdf::Geometry::SPHERE: {
        v.shape = VisualShape::Sphere;
        v.size = Vec3(static_cast<const urdf::Sphere&>(*uv->geometry).radius, 0, 0);
        break;
      }
      case urdf::Geometry::MESH: {
        const auto& g = static_cast<const urdf::Mesh&>(*uv->geometry);
        v.shape = VisualShape::Mesh;
        v.filename = mesh_path(g.filename, urdf_dir);
        v.scale = to_vec(g.scale);
        break;
      }
      default:
        continue;
    }
    if (uv->material && uv->material->texture_filename.empty()) {
      const urdf::Color& c = uv->material->color;
      v.rgba = Eigen::Vector4d(c.r, c.g, c.b, c.a);
    }
    out.push_back(v);
  }
  return out;
}

class TreeBuilder {
 public:
  TreeBuilder(const urdf::ModelInterface& urdf, const UrdfOptions& opt, std::string urdf_dir,
              std::vector<std::string>* warnings)
      : urdf_(urdf), opt_(opt), urdf_dir_(std::move(urdf_dir)), warnings_(warnings) {}

  Model build() {
    const urdf::LinkConstSharedPtr root = urdf_.getRoot();
    if (!root) throw UrdfError("URDF has no root link");
    check_tree();
    int root_body = -1;
    if (opt_.base == BaseJoint::Fixed) {
      visit(*root, -1, SE3::Identity());
    } else {
      const bool floating = opt_.base == BaseJoint::Floating || opt_.base == BaseJoint::Euler;
      root_body = add_chain(floating ? floating_chain() : planar_chain(opt_.planar_normal),
                            floating ? kFloatingSuffix : kPlanarSuffix, root->name, root->name + "_base",
                            -1, SE3::Identity());
      visit(*root, root_body, SE3::Identity());
    }
    if (specs_.empty())
      throw UrdfError("URDF '" + urdf_.getName() + "' has no movable joint: with base='fixed' it is one rigid body "
                      "welded to the world; load it with base='floating' (or 'planar') to let it move");
    Model model;
    for (std::size_t i = 0; i < specs_.size(); ++i) {
      BodySpec s = specs_[i];
      const SpatialInertia& I = inertia_[i];
      s.mass = I.m;
      s.com = I.m > 0 ? Vec3(I.h / I.m) : Vec3::Zero();
      s.inertia = I.m > 0 ? Mat3(I.I + I.m * hat(s.com) * hat(s.com)) : Mat3::Zero();
      s.inertia = 0.5 * (s.inertia + s.inertia.transpose()).eval();
      model.add_body(s, TriangleInequality::Accept);  // each link's inertia was checked (and warned about)
    }
    for (const Visual& v : visuals_) model.add_visual(v);
    if (opt_.base == BaseJoint::Floating) model.set_rotation_chart(3);
    return model;
  }

 private:
  // urdfdom keeps the last parent joint of a link; a link that is the child of two joints
  // closes a kinematic loop, which a tree cannot hold.
  void check_tree() const {
    for (const auto& [name, joint] : urdf_.joints_) {
      const urdf::LinkConstSharedPtr child = urdf_.getLink(joint->child_link_name);
      if (!child) throw UrdfError("joint '" + name + "' names unknown child link '" + joint->child_link_name + "'");
      if (!child->parent_joint || child->parent_joint->name != name)
        throw UrdfError("link '" + child->name + "' is the child of more than one joint ('" + name +
                        "' and '" + (child->parent_joint ? child->parent_joint->name : "?") +
                        "'): kinematic loops are not supported");
    }
  }

  // Adds `link` (whose frame is X in the frame of body `body`, -1 = world) and its subtree.
  void visit(const urdf::Link& link, int body, const SE3& X) {
    if (body >= 0) inertia_[body] += link_inertia(link, warnings_).transformed(X);
    else link_inertia(link, warnings_);  // still validated when welded to the world
    for (Visual& v : link_visuals(link, body, X, urdf_dir_)) visuals_.push_back(std::move(v));
    for (const urdf::JointSharedPtr& joint : link.child_joints) {
      const urdf::LinkConstSharedPtr child = urdf_.getLink(joint->child_link_name);
      const SE3 Xj = X * to_se3(joint->parent_to_joint_origin_transform);
      JointLimits lim;
      if (joint->limits && joint->type != urdf::Joint::CONTINUOUS) {
        lim.lower = joint->limits->lower;
        lim.upper = joint->limits->upper;
      }
      if (joint->limits) {
        lim.velocity = joint->limits->velocity;
        lim.effort = joint->limits->effort;
      }
      switch (joint->type) {
        case urdf::Joint::FIXED:
          visit(*child, body, Xj);
          break;
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS:
        case urdf::Joint::PRISMATIC: {
          BodySpec s;
          s.name = child->name;
          s.joint_name = joint->name;
          s.parent = body;
          s.type = joint->type == urdf::Joint::PRISMATIC ? JointType::Prismatic : JointType::Revolute;
          s.axis = to_vec(joint->axis);
          if (s.axis.norm() < 1e-12) throw UrdfError("joint '" + joint->name + "' has a zero axis");
          s.placement = Xj;
          s.limits = lim;
          if (joint->mimic) s.mimic = Mimic{joint->mimic->joint_name, joint->mimic->multiplier, joint->mimic->offset};
          if (joint->dynamics) {
            s.damping = joint->dynamics->damping;
            s.friction = joint->dynamics->friction;
          }
          visit(*child, push(s), SE3::Identity());
          break;
        }
        case urdf::Joint::FLOATING:
        case urdf::Joint::PLANAR: {
          const bool floating = joint->type == urdf::Joint::FLOATING;
          if (!opt_.expand_joints)
            throw UrdfError("joint '" + joint->name + "' is " + (floating ? "floating" : "planar") +
                            ": hovi supports 1-DoF joints; pass expand_joints=True to expand it into "
                            "1-DoF joints");
          const int last = add_chain(floating ? floating_chain() : planar_chain(to_vec(joint->axis)),
                                     floating ? kFloatingSuffix : kPlanarSuffix, child->name, joint->name,
                                     body, Xj);
          visit(*child, last, SE3::Identity());
          break;
        }
        default:
          throw UrdfError("joint '" + joint->name + "' has an unknown or unsupported type");
      }
    }
  }

  // Expands a multi-DoF joint into massless virtual bodies; returns the last (the real link).
  int add_chain(const JointChain& chain, const char* const* suffix, const std::string& link_name,
                const std::string& joint_name, int parent, const SE3& placement) {
    int body = parent;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      BodySpec s;
      const bool last = k + 1 == chain.size();
      s.name = last ? link_name : link_name + suffix[k];
      s.joint_name = joint_name + suffix[k];
      s.parent = body;
      s.type = chain[k].first;
      s.axis = chain[k].second;
      s.placement = k == 0 ? placement : SE3::Identity();
      body = push(s);
    }
    return body;
  }

  int push(const BodySpec& s) {
    specs_.push_back(s);
    inertia_.emplace_back();
    return static_cast<int>(specs_.size()) - 1;
  }

  const urdf::ModelInterface& urdf_;
  const UrdfOptions& opt_;
  const std::string urdf_dir_;  // directory of the URDF file, empty for XML text
  std::vector<std::string>* warnings_;
  std::vector<Visual> visuals_;
  std::vector<BodySpec> specs_;
  std::vector<SpatialInertia> inertia_;  // lumped inertia of each body about its joint frame
};

bool is_xml(const std::string& source) {
  const auto first = source.find_first_not_of(" \t\r\n");
  return first != std::string::npos && source[first] == '<';
}

// The absolute directory of a URDF file, for relative mesh names.
std::string source_directory(const std::string& path) {
  return std::filesystem::absolute(path).parent_path().string();
}

std::string read_source(const std::string& source) {
  if (is_xml(source)) return source;
  std::ifstream in(source);
  if (!in) throw UrdfError("cannot open URDF file '" + source + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

Model model_from_urdf(const std::string& source, const UrdfOptions& options, std::vector<std::string>* warnings) {
  const std::string xml = read_source(source);
  check_numbers(xml);
  urdf::ModelInterfaceSharedPtr urdf;
  std::string messages;
  {
    MessageCapture capture;
    try {
      urdf = urdf::parseURDF(xml);
    } catch (const std::exception& e) {
      capture.text += std::string(capture.text.empty() ? "" : "; ") + e.what();
    }
    messages = capture.text;
  }
  if (!urdf) throw UrdfError("malformed or invalid URDF: " + (messages.empty() ? "urdfdom could not parse it" : messages));
  try {
    return TreeBuilder(*urdf, options, is_xml(source) ? std::string() : source_directory(source), warnings).build();
  } catch (const UrdfError&) {
    throw;
  } catch (const ModelError& e) {  // what the model refuses (an inertia, a lumped overflow, a visual) is the URDF's fault
    throw UrdfError(e.what());
  }
}

}  // namespace hovi
