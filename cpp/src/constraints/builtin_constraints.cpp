#include "hovi/constraints/builtin_constraints.hpp"

#include <cstring>

#include "hovi/errors.hpp"

namespace hovi {

namespace {
void check_body(const Model& model, int body, const char* kind) {
  if (body < 0 || body >= model.n())
    throw ModelError(std::string(kind) + " constraint: body index " + std::to_string(body) + " out of range");
}
// Rows j on the path from body b to the root of the point Jacobian of world point x:
// d x / d q_j = v_j + ω_j × x for S̄_j = (ω_j, v_j); other columns zero.
void add_point_jacobian(const KinematicsView& kin, int b, const Vec3& x, double sign,
                        const Eigen::Matrix<double, Eigen::Dynamic, 3>& P, Eigen::Ref<MatX> J) {
  for (int j = b; j >= 0; j = kin.model.parent[j]) {
    const Twist& S = kin.twist(j);
    J.col(j) += sign * (P * (S.tail<3>() + S.head<3>().cross(x)));
  }
}
const char* const kAxisNames = "xyz";
}  // namespace

Eigen::Matrix<double, Eigen::Dynamic, 3> axes_selector(const std::string& axes) {
  if (axes.empty() || axes.size() > 3) throw ModelError("axes must be a non-empty subset of 'xyz', got '" + axes + "'");
  Eigen::Matrix<double, Eigen::Dynamic, 3> P = Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(axes.size(), 3);
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const char* at = std::strchr(kAxisNames, axes[k]);
    if (!at || axes[k] == '\0') throw ModelError("axes must be a subset of 'xyz', got '" + axes + "'");
    if (axes.find(axes[k]) != k) throw ModelError("axes repeats '" + std::string(1, axes[k]) + "'");
    P(k, at - kAxisNames) = 1;
  }
  return P;
}

// ---- PointConstraint -------------------------------------------------------------------------
PointConstraint::PointConstraint(int body, const Vec3& point, const Vec3& target, const std::string& axes)
    : body_(body), point_(point), target_(target), axes_(axes), P_(axes_selector(axes)) {}

void PointConstraint::check(const Model& model) const { check_body(model, body_, kind()); }

void PointConstraint::value(const KinematicsView& kin, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX> h) const {
  h = P_ * (kin.pose(body_).act(point_) - target_);
}

void PointConstraint::jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const {
  J.setZero();
  add_point_jacobian(kin, body_, kin.pose(body_).act(point_), 1.0, P_, J);
}

void PointConstraint::add_force_elements(Model& aug, int first) const {
  for (int k = 0; k < dim(); ++k)
    aug.add_wrench(std::make_shared<PointWrench>(body_, point_, P_.row(k).transpose(), Vec3::Zero(),
                                                 PointWrench::Frame::World, first + k));
}

void PointConstraint::save(ByteWriter& out) const {
  out.put(body_);
  out.put(point_);
  out.put(target_);
  out.put(axes_);
}

std::shared_ptr<const PointConstraint> PointConstraint::load(ByteReader& in) {
  const int body = in.get<int>();
  const Vec3 point = in.get_matrix<Vec3>(), target = in.get_matrix<Vec3>();
  return std::make_shared<PointConstraint>(body, point, target, in.get_string());
}

// ---- LoopConstraint --------------------------------------------------------------------------
LoopConstraint::LoopConstraint(int body1, const Vec3& point1, int body2, const Vec3& point2, const std::string& axes)
    : body1_(body1), body2_(body2), point1_(point1), point2_(point2), axes_(axes), P_(axes_selector(axes)) {}

void LoopConstraint::check(const Model& model) const {
  check_body(model, body1_, kind());
  check_body(model, body2_, kind());
  if (body1_ == body2_) throw ModelError("loop constraint: the two bodies must differ");
}

void LoopConstraint::value(const KinematicsView& kin, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX> h) const {
  h = P_ * (kin.pose(body1_).act(point1_) - kin.pose(body2_).act(point2_));
}

void LoopConstraint::jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const {
  J.setZero();
  add_point_jacobian(kin, body1_, kin.pose(body1_).act(point1_), 1.0, P_, J);
  add_point_jacobian(kin, body2_, kin.pose(body2_).act(point2_), -1.0, P_, J);
}

void LoopConstraint::add_force_elements(Model& aug, int first) const {
  for (int k = 0; k < dim(); ++k) {
    const Vec3 f = P_.row(k).transpose();
    aug.add_wrench(std::make_shared<PointWrench>(body1_, point1_, f, Vec3::Zero(), PointWrench::Frame::World, first + k));
    aug.add_wrench(std::make_shared<PointWrench>(body2_, point2_, -f, Vec3::Zero(), PointWrench::Frame::World, first + k));
  }
}

void LoopConstraint::save(ByteWriter& out) const {
  out.put(body1_);
  out.put(point1_);
  out.put(body2_);
  out.put(point2_);
  out.put(axes_);
}

std::shared_ptr<const LoopConstraint> LoopConstraint::load(ByteReader& in) {
  const int body1 = in.get<int>();
  const Vec3 point1 = in.get_matrix<Vec3>();
  const int body2 = in.get<int>();
  const Vec3 point2 = in.get_matrix<Vec3>();
  return std::make_shared<LoopConstraint>(body1, point1, body2, point2, in.get_string());
}

// ---- OrientationConstraint -------------------------------------------------------------------
namespace {
// (body axis a, world axis index b) of the three equations
constexpr int kAlignA[3] = {1, 2, 0};
constexpr int kAlignB[3] = {2, 0, 1};
}  // namespace

OrientationConstraint::OrientationConstraint(int body, const Mat3& R0) : body_(body), R0_(R0) {
  if ((R0.transpose() * R0 - Mat3::Identity()).norm() > 1e-9 || R0.determinant() < 0)
    throw ModelError("orientation constraint: the target is not a rotation matrix");
}

void OrientationConstraint::check(const Model& model) const { check_body(model, body_, kind()); }

void OrientationConstraint::value(const KinematicsView& kin, const Eigen::Ref<const VecX>&, Eigen::Ref<VecX> h) const {
  const Mat3& R = kin.pose(body_).R;
  for (int c = 0; c < 3; ++c) h[c] = R.col(kAlignA[c]).dot(R0_.col(kAlignB[c]));
}

void OrientationConstraint::jacobian(const KinematicsView& kin, Eigen::Ref<MatX> J) const {
  J.setZero();
  const Mat3& R = kin.pose(body_).R;
  for (int c = 0; c < 3; ++c) {
    const Vec3 axis = R.col(kAlignA[c]).cross(R0_.col(kAlignB[c]));  // dh_c = ω · (R a × d)
    for (int j = body_; j >= 0; j = kin.model.parent[j]) J(c, j) = kin.twist(j).head<3>().dot(axis);
  }
}

void OrientationConstraint::add_force_elements(Model& aug, int first) const {
  for (int c = 0; c < 3; ++c)
    aug.add_wrench(std::make_shared<AlignmentTorque>(body_, Vec3::Unit(kAlignA[c]), R0_.col(kAlignB[c]), first + c));
}

void OrientationConstraint::save(ByteWriter& out) const {
  out.put(body_);
  out.put(R0_);
}

std::shared_ptr<const OrientationConstraint> OrientationConstraint::load(ByteReader& in) {
  const int body = in.get<int>();
  return std::make_shared<OrientationConstraint>(body, in.get_matrix<Mat3>());
}

// ---- JointCoupling ---------------------------------------------------------------------------
JointCoupling::JointCoupling(const VecX& coefficients, double offset) : c_(coefficients), offset_(offset) {
  if (!c_.allFinite() || c_.cwiseAbs().maxCoeff() == 0)
    throw ModelError("joint coupling: the coefficients must be finite and not all zero");
}

void JointCoupling::check(const Model& model) const {
  if (c_.size() != model.n())
    throw ModelError("joint coupling: " + std::to_string(c_.size()) + " coefficients for " +
                     std::to_string(model.n()) + " joints");
}

void JointCoupling::value(const KinematicsView&, const Eigen::Ref<const VecX>& q, Eigen::Ref<VecX> h) const {
  h[0] = c_.dot(q) - offset_;
}

void JointCoupling::jacobian(const KinematicsView&, Eigen::Ref<MatX> J) const { J.row(0) = c_.transpose(); }

void JointCoupling::add_force_elements(Model& aug, int first) const { aug.joint_forces.actuation.col(first) = c_; }

void JointCoupling::save(ByteWriter& out) const {
  out.put(c_);
  out.put(offset_);
}

std::shared_ptr<const JointCoupling> JointCoupling::load(ByteReader& in) {
  const VecX c = in.get_matrix<VecX>();
  return std::make_shared<JointCoupling>(c, in.get<double>());
}

// ---- AlignmentTorque -------------------------------------------------------------------------
AlignmentTorque::AlignmentTorque(int body, const Vec3& body_axis, const Vec3& world_axis, int control)
    : BodyWrench(body), a_(body_axis), d_(world_axis), control_(control) {}

Wrench AlignmentTorque::value(const SE3& g, const Twist&, const VecX& u) const {
  Wrench F = Wrench::Zero();
  F.head<3>() = u[control_] * (g.R * a_).cross(d_);
  return F;
}

void AlignmentTorque::add_derivatives(const SE3& g, const Twist&, const VecX& u, Mat6& D1, Mat6&) const {
  D1.topLeftCorner<3, 3>() += u[control_] * hat(d_) * hat(g.R * a_);
}

void AlignmentTorque::add_control_jacobian(const SE3& g, const Twist&, const VecX&, Eigen::Ref<MatX> Du) const {
  Du.col(control_).head<3>() += (g.R * a_).cross(d_);
}

void AlignmentTorque::save(ByteWriter& out) const {
  out.put(body());
  out.put(a_);
  out.put(d_);
  out.put(control_);
}

std::shared_ptr<const AlignmentTorque> AlignmentTorque::load(ByteReader& in) {
  const int body = in.get<int>();
  const Vec3 a = in.get_matrix<Vec3>(), d = in.get_matrix<Vec3>();
  return std::make_shared<AlignmentTorque>(body, a, d, in.get<int>());
}

}  // namespace hovi
