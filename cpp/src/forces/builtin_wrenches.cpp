#include "hovi/forces/builtin_wrenches.hpp"

#include <cmath>
#include <sstream>

#include "hovi/errors.hpp"

namespace hovi {

PointWrench::PointWrench(int body, const Vec3& point, const Vec3& force, const Vec3& torque, Frame frame, int control)
    : BodyWrench(body), point_(point), force_(force), torque_(torque), frame_(frame), control_(control) {
  if (!point.allFinite() || !force.allFinite() || !torque.allFinite())
    throw ModelError("point wrench on body " + std::to_string(body) + ": point, force and torque must be finite");
}

Wrench PointWrench::unit_value(const SE3& g) const {
  if (frame_ == Frame::World) {
    Wrench F;
    F.head<3>() = torque_ + g.act(point_).cross(force_);
    F.tail<3>() = force_;
    return F;
  }
  Wrench Fb;  // body wrench about the COM
  Fb.head<3>() = torque_ + point_.cross(force_);
  Fb.tail<3>() = force_;
  return AdInvT(g, Fb);
}

Wrench PointWrench::value(const SE3& g, const Twist&, const VecX& u) const { return scale(u) * unit_value(g); }

void PointWrench::add_derivatives(const SE3& g, const Twist&, const VecX& u, Mat6& D1, Mat6&) const {
  if (frame_ == Frame::World) D1 += scale(u) * world_force_D1(force_, g.act(point_));
  else D1 -= adD(value(g, Twist::Zero(), u));  // body-fixed wrenches: D1 = -ad^D_F̄
}

void PointWrench::add_control_jacobian(const SE3& g, const Twist&, const VecX&, Eigen::Ref<MatX> Du) const {
  if (control_ >= 0) Du.col(control_) += unit_value(g);
}

bool PointWrench::world_point_force(Vec3& point, Vec3& force, int& control) const {
  if (frame_ != Frame::World || !torque_.isZero(0)) return false;   // a torque or a turning force has no potential
  point = point_;
  force = force_;
  control = control_;
  return true;
}

void PointWrench::save(ByteWriter& out) const {
  out.put(body());
  out.put(point_);
  out.put(force_);
  out.put(torque_);
  out.put(static_cast<int>(frame_ == Frame::World ? 0 : 1));
  out.put(control_);
}

std::shared_ptr<const PointWrench> PointWrench::load(ByteReader& in) {
  const int body = in.get<int>();
  const Vec3 point = in.get_matrix<Vec3>(), force = in.get_matrix<Vec3>(), torque = in.get_matrix<Vec3>();
  const int frame = in.get<int>();
  if (frame != 0 && frame != 1) ByteReader::corrupt();
  return std::make_shared<PointWrench>(body, point, force, torque, frame == 0 ? Frame::World : Frame::Body, in.get<int>());
}

BodyDrag::BodyDrag(int body, double linear, double angular)
    : BodyWrench(body), C_(linear, Vec3::Zero(), angular * Mat3::Identity()) {
  if (!(std::isfinite(linear) && linear >= 0 && std::isfinite(angular) && angular >= 0)) {
    std::ostringstream os;  // a negative coefficient would feed energy in
    os << "drag on body " << body << ": coefficients must be finite and non-negative, got linear " << linear
       << ", angular " << angular;
    throw ModelError(os.str());
  }
}

Wrench BodyDrag::value(const SE3& g, const Twist& v, const VecX&) const { return -(C_.transformed(g) * v); }

void BodyDrag::add_derivatives(const SE3& g, const Twist& v, const VecX&, Mat6& D1, Mat6& D2) const {
  const Mat6 Cbar = C_.transformed(g).matrix();
  const Wrench F = -(Cbar * v);
  D2 -= Cbar;
  D1 -= adD(F) + Cbar * ad(v);
}

void BodyDrag::save(ByteWriter& out) const {
  out.put(body());
  out.put(C_.m);        // linear
  out.put(C_.I(0, 0));  // angular
}

std::shared_ptr<const BodyDrag> BodyDrag::load(ByteReader& in) {
  const int body = in.get<int>();
  const double linear = in.get<double>();
  return std::make_shared<BodyDrag>(body, linear, in.get<double>());
}

}  // namespace hovi
