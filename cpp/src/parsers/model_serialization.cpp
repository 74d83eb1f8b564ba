#include "hovi/parsers/model_serialization.hpp"

#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/errors.hpp"
#include "hovi/util/byte_stream.hpp"

namespace hovi {

namespace {

constexpr const char* kMagic = "hovi.Model";
// 2: joint armature; 3: the header carries the payload's length and checksum; 4: the rotation chart.
constexpr std::uint32_t kVersion = 4;
constexpr std::uint32_t kByteOrder = 0x01020304;  // reads back as 0x04030201 on the other byte order
constexpr std::uint32_t kOtherByteOrder = 0x04030201;

// FNV-1a (64 bit) of the payload. Each step h = (h ^ byte) * prime is a bijection of h, so bytes that
// differ from the written ones in one place (or in a run shorter than 8 bytes) always change it; other
// damage goes unnoticed with probability 2^-64.
std::uint64_t checksum(const char* data, std::size_t size) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t k = 0; k < size; ++k) {
    h ^= static_cast<unsigned char>(data[k]);
    h *= 1099511628211ull;
  }
  return h;
}

void put(ByteWriter& out, const SE3& g) {
  out.put(g.R);
  out.put(g.p);
}
SE3 get_se3(ByteReader& in) {
  const Mat3 R = in.get_matrix<Mat3>();
  return SE3(R, in.get_matrix<Vec3>());
}

void put(ByteWriter& out, const BodySpec& s) {
  out.put(s.name);
  out.put(s.joint_name);
  out.put(s.parent);
  out.put(static_cast<int>(s.type == JointType::Revolute ? 0 : 1));
  out.put(s.axis);
  put(out, s.placement);
  out.put(s.mass);
  out.put(s.com);
  out.put(s.inertia);
  for (double x : {s.limits.lower, s.limits.upper, s.limits.velocity, s.limits.effort}) out.put(x);
  out.put(static_cast<int>(s.mimic.has_value()));
  if (s.mimic) {
    out.put(s.mimic->joint);
    out.put(s.mimic->multiplier);
    out.put(s.mimic->offset);
  }
  out.put(s.damping);
  out.put(s.friction);
}
BodySpec get_spec(ByteReader& in) {
  BodySpec s;
  s.name = in.get_string();
  s.joint_name = in.get_string();
  s.parent = in.get<int>();
  const int type = in.get<int>();
  if (type != 0 && type != 1) ByteReader::corrupt();
  s.type = type == 0 ? JointType::Revolute : JointType::Prismatic;
  s.axis = in.get_matrix<Vec3>();
  s.placement = get_se3(in);
  s.mass = in.get<double>();
  s.com = in.get_matrix<Vec3>();
  s.inertia = in.get_matrix<Mat3>();
  for (double* x : {&s.limits.lower, &s.limits.upper, &s.limits.velocity, &s.limits.effort}) *x = in.get<double>();
  if (in.get<int>()) {
    Mimic m;
    m.joint = in.get_string();
    m.multiplier = in.get<double>();
    m.offset = in.get<double>();
    s.mimic = m;
  }
  s.damping = in.get<double>();
  s.friction = in.get<double>();
  return s;
}

void put(ByteWriter& out, const Visual& v) {
  out.put(v.body);
  out.put(v.link);
  out.put(static_cast<int>(v.shape));
  out.put(v.size);
  out.put(v.filename);
  out.put(v.scale);
  put(out, v.origin);
  out.put(static_cast<int>(v.rgba.has_value()));
  if (v.rgba) out.put(*v.rgba);
}
Visual get_visual(ByteReader& in) {
  Visual v;
  v.body = in.get<int>();
  v.link = in.get_string();
  const int shape = in.get<int>();
  if (shape < 0 || shape > static_cast<int>(VisualShape::Mesh)) ByteReader::corrupt();
  v.shape = static_cast<VisualShape>(shape);
  v.size = in.get_matrix<Vec3>();
  v.filename = in.get_string();
  v.scale = in.get_matrix<Vec3>();
  v.origin = get_se3(in);
  if (in.get<int>()) v.rgba = in.get_matrix<Eigen::Vector4d>();
  return v;
}

std::shared_ptr<const BodyWrench> get_wrench(ByteReader& in) {
  const std::string kind = in.get_string();
  if (kind == "point_wrench") return PointWrench::load(in);
  if (kind == "drag") return BodyDrag::load(in);
  if (kind == "alignment_torque") return AlignmentTorque::load(in);
  throw ModelError("the serialised model has a body wrench of unknown kind '" + kind + "'");
}

std::shared_ptr<const Constraint> get_constraint(ByteReader& in) {
  const std::string kind = in.get_string();
  if (kind == "point") return PointConstraint::load(in);
  if (kind == "loop") return LoopConstraint::load(in);
  if (kind == "orientation") return OrientationConstraint::load(in);
  if (kind == "joint_coupling") return JointCoupling::load(in);
  throw ModelError("the serialised model has a constraint of unknown kind '" + kind + "'");
}

// A stored quantity that add_body derived again: equal up to round-off (a normalised axis
// normalised again may move by an ulp), or the record is corrupt.
template <class A, class B>
void check_close(const A& stored, const B& derived) {
  if (!stored.allFinite() || (stored - derived).norm() > 1e-9 * (1 + derived.norm())) ByteReader::corrupt();
}

}  // namespace

std::string serialize(const Model& model) {
  ByteWriter out;  // the payload; the header goes before it
  out.put(model.n());
  for (int i = 0; i < model.n(); ++i) {
    put(out, model.spec[i]);
    out.put(model.S[i]);
    put(out, model.g_parent0[i]);
    out.put(model.M[i].m);
    out.put(model.M[i].h);
    out.put(model.M[i].I);
  }
  out.put(model.gravity);
  const JointForces& f = model.joint_forces;
  out.put(f.stiffness);
  out.put(f.preload);
  out.put(f.damping);
  out.put(f.actuation);
  out.put(model.armature);
  out.put(static_cast<int>(model.wrenches.size()));
  for (const auto& w : model.wrenches) {
    out.put(std::string(w->kind()));
    w->save(out);
  }
  out.put(static_cast<int>(model.constraints.size()));
  for (const auto& c : model.constraints) {
    out.put(std::string(c->kind()));
    c->save(out);
  }
  out.put(static_cast<int>(model.visuals.size()));
  for (const Visual& v : model.visuals) put(out, v);
  out.put(model.rotation_chart);
  const std::string& payload = out.bytes();
  ByteWriter header;
  header.put(std::string(kMagic));
  header.put(kVersion);
  header.put(kByteOrder);
  header.put(static_cast<std::uint64_t>(payload.size()));
  header.put(checksum(payload.data(), payload.size()));
  return header.bytes() + payload;
}

Model deserialize(const std::string& bytes) {
  ByteWriter magic;
  magic.put(std::string(kMagic));
  if (bytes.compare(0, magic.bytes().size(), magic.bytes()) != 0) throw ModelError("not a serialised hovi model");
  ByteReader head(bytes);
  head.get_string();
  const auto version = head.get<std::uint32_t>();
  if (version != kVersion)
    throw ModelError("a serialised hovi model of format " + std::to_string(version) + ": this hovi reads format " +
                     std::to_string(kVersion) + " (pickle the model again with this hovi)");
  const auto order = head.get<std::uint32_t>();
  if (order == kOtherByteOrder)
    throw ModelError("the serialised model was written on a machine of the other byte order");
  if (order != kByteOrder) throw ModelError("model bytes are corrupted (bad header)");
  const auto size = head.get<std::uint64_t>();
  const auto sum = head.get<std::uint64_t>();
  const std::size_t start = head.position();
  if (size != bytes.size() - start)
    throw ModelError("the serialised model is truncated or corrupt: its header announces " + std::to_string(size) +
                     " bytes of model data, " + std::to_string(bytes.size() - start) + " follow");
  if (checksum(bytes.data() + start, bytes.size() - start) != sum)
    throw ModelError("model bytes are corrupted (checksum mismatch): they are not the bytes hovi wrote");
  const std::string payload = bytes.substr(start);
  ByteReader in(payload);
  Model model;
  const int n = in.get<int>();
  if (n < 0) ByteReader::corrupt();
  for (int i = 0; i < n; ++i) {
    const BodySpec spec = get_spec(in);
    const Twist S = in.get_matrix<Twist>();
    const SE3 g = get_se3(in);
    const double mass = in.get<double>();
    const Vec3 h = in.get_matrix<Vec3>();
    const Mat3 I = in.get_matrix<Mat3>();
    // Checks the body (keeping an inertia that violates the triangle inequality, as a URDF model may
    // have); the stored derived quantities then replace its own.
    model.add_body(spec, TriangleInequality::Accept);
    check_close(S, model.S[i]);
    check_close(g.matrix(), model.g_parent0[i].matrix());
    check_close(Eigen::Matrix<double, 1, 1>(mass), Eigen::Matrix<double, 1, 1>(model.M[i].m));
    check_close(h, model.M[i].h);
    check_close(I, model.M[i].I);
    model.spec[i] = spec;
    model.S[i] = S;
    model.g_parent0[i] = g;
    model.M[i] = SpatialInertia(mass, h, I);
  }
  model.gravity = in.get_matrix<Vec3>();
  JointForces& f = model.joint_forces;
  f.stiffness = in.get_matrix<VecX>();
  f.preload = in.get_matrix<VecX>();
  f.damping = in.get_matrix<VecX>();
  f.actuation = in.get_matrix<MatX>();
  if (!model.gravity.allFinite() || f.stiffness.size() != n || f.preload.size() != n || f.damping.size() != n ||
      f.actuation.rows() != n || !f.stiffness.allFinite() || !f.preload.allFinite() || !f.damping.allFinite() ||
      !f.actuation.allFinite())
    ByteReader::corrupt();
  const VecX armature = in.get_matrix<VecX>();
  if (armature.size() != n) ByteReader::corrupt();
  for (int i = 0; i < n; ++i) model.set_armature(i, armature[i]);  // checks each value
  const int n_wrenches = in.get<int>();
  for (int k = 0; k < n_wrenches; ++k) model.add_wrench(get_wrench(in));
  const int n_constraints = in.get<int>();
  for (int k = 0; k < n_constraints; ++k) model.add_constraint(get_constraint(in));
  const int n_visuals = in.get<int>();
  for (int k = 0; k < n_visuals; ++k) model.add_visual(get_visual(in));
  const int chart = in.get<int>();
  if (chart >= 0) model.set_rotation_chart(chart);  // checks it
  if (!in.at_end()) ByteReader::corrupt();
  return model;
}

}  // namespace hovi
