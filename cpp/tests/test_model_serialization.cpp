// serialize / deserialize (model_serialization.hpp): every field comes back bit for bit, for a
// model with every kind of force element, constraint and visual; bad bytes throw ModelError.
#include <gtest/gtest.h>

#include "test_models.hpp"
#include "hovi/constraints/builtin_constraints.hpp"
#include "hovi/forces/builtin_wrenches.hpp"
#include "hovi/errors.hpp"
#include "hovi/parsers/model_serialization.hpp"

using namespace hovi;

namespace {

Model everything() {
  Model m = test_models::forced_pendulum();
  m.gravity = Vec3(0.1, -0.2, -9.7);
  m.spec[1].mimic = Mimic{"pendulum_joint_0", 0.5, 0.1};
  m.spec[2].limits.lower = -1.2;
  m.spec[2].damping = 0.3;
  const int c = m.add_control();
  m.add_wrench(std::make_shared<PointWrench>(2, Vec3(0.1, 0, 0.2), Vec3(1, 2, 3), Vec3(0, 0.1, 0), PointWrench::Frame::Body, c));
  m.add_wrench(std::make_shared<PointWrench>(0, Vec3::Zero(), Vec3(0, 0, 1), Vec3::Zero(), PointWrench::Frame::World));
  m.add_wrench(std::make_shared<BodyDrag>(3, 0.7, 0.2));
  m.set_armature(3, 0.02);
  m.add_wrench(std::make_shared<AlignmentTorque>(1, Vec3::UnitY(), Vec3::UnitZ(), c));
  m.add_constraint(std::make_shared<PointConstraint>(4, Vec3(0, 0, -0.25), Vec3(0.1, 0, -2), "xz"));
  m.add_constraint(std::make_shared<LoopConstraint>(1, Vec3(0.1, 0, 0), 3, Vec3(0, 0.1, 0), "y"));
  m.add_constraint(std::make_shared<OrientationConstraint>(2, Mat3::Identity()));
  m.add_constraint(std::make_shared<JointCoupling>((VecX(5) << 1, -1, 0, 0, 0.5).finished(), 0.2));
  Visual v;
  v.body = 2;
  v.link = "pendulum_link_2";
  v.shape = VisualShape::Mesh;
  v.filename = "/meshes/link.stl";
  v.scale = Vec3(0.001, 0.001, 0.002);
  v.rgba = Eigen::Vector4d(0.1, 0.2, 0.3, 1.0);
  m.add_visual(v);
  Visual w;
  w.shape = VisualShape::Cylinder;
  w.size = Vec3(0.05, 0.4, 0);
  m.add_visual(w);
  return m;
}

}  // namespace

TEST(ModelSerialization, RoundTripIsExact) {
  const Model m = everything();
  const std::string bytes = serialize(m);
  const Model r = deserialize(bytes);
  EXPECT_EQ(serialize(r), bytes);  // every field, written the same way, bit for bit
  ASSERT_EQ(r.n(), m.n());
  EXPECT_EQ(r.parent, m.parent);
  EXPECT_EQ(r.armature, m.armature);
  EXPECT_EQ(r.children, m.children);
  for (int i = 0; i < m.n(); ++i) {
    EXPECT_EQ(r.S[i], m.S[i]);
    EXPECT_EQ(r.g_parent0[i].matrix(), m.g_parent0[i].matrix());
    EXPECT_EQ(r.M[i].I, m.M[i].I);
    EXPECT_EQ(r.spec[i].axis, m.spec[i].axis);
  }
  EXPECT_EQ(r.spec[1].mimic->joint, "pendulum_joint_0");
  EXPECT_EQ(r.joint_forces.actuation, m.joint_forces.actuation);
  EXPECT_EQ(r.joint_forces.preload, m.joint_forces.preload);
  EXPECT_EQ(r.wrenches.size(), 4u);
  EXPECT_EQ(r.n_constraints(), m.n_constraints());
  EXPECT_EQ(r.visuals[0].rgba.value(), m.visuals[0].rgba.value());
  EXPECT_EQ(r.visuals[1].size, m.visuals[1].size);
  EXPECT_EQ(r.gravity, m.gravity);
}

TEST(ModelSerialization, BadBytesThrow) {
  const std::string bytes = serialize(everything());
  EXPECT_THROW(deserialize(""), ModelError);
  EXPECT_THROW(deserialize("not a model at all"), ModelError);
  for (std::size_t cut : {bytes.size() - 1, bytes.size() / 2, std::size_t(30)})
    EXPECT_THROW(deserialize(bytes.substr(0, cut)), ModelError) << cut;
  EXPECT_THROW(deserialize(bytes + "x"), ModelError);
  std::string flipped = bytes;
  flipped[18] ^= 0x7f;  // the format version (after the 8-byte length and "hovi.Model")
  EXPECT_THROW(deserialize(flipped), ModelError);
}

// The header's checksum of the model data: every byte changed anywhere (header or data, in the low or
// the high bit) is refused, never read as another model; a change in the data says so.
TEST(ModelSerialization, EveryChangedByteIsRefused) {
  const std::string bytes = serialize(everything());
  const std::size_t header = 8 + 10 + 4 + 4 + 8 + 8;  // magic, version, byte order, length, checksum
  for (std::size_t k = 0; k < bytes.size(); ++k)
    for (char bit : {char(0x01), char(0x80)}) {
      std::string changed = bytes;
      changed[k] ^= bit;
      try {
        deserialize(changed);
        ADD_FAILURE() << "byte " << k << " changed was loaded";
      } catch (const ModelError& e) {
        if (k >= header) EXPECT_STREQ(e.what(), "model bytes are corrupted (checksum mismatch): they are not the bytes hovi wrote") << k;
      }
    }
}

TEST(ModelSerialization, AKindDefinedElsewhereCannotBeSaved) {
  struct Custom : BodyWrench {
    Custom() : BodyWrench(0) {}
    Wrench value(const SE3&, const Twist&, const VecX&) const override { return Wrench::Zero(); }
    void add_derivatives(const SE3&, const Twist&, const VecX&, Mat6&, Mat6&) const override {}
    void add_control_jacobian(const SE3&, const Twist&, const VecX&, Eigen::Ref<MatX>) const override {}
    const char* kind() const override { return "custom"; }
  };
  Model m = models::pendulum(2);
  m.add_wrench(std::make_shared<Custom>());
  EXPECT_THROW(serialize(m), ModelError);
}
