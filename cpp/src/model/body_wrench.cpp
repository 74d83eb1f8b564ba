#include "hovi/model/body_wrench.hpp"

#include "hovi/errors.hpp"

namespace hovi {

void BodyWrench::save(ByteWriter&) const {
  throw ModelError(std::string("a body wrench of kind '") + kind() + "' cannot be serialised (it does not implement save)");
}

Mat6 world_force_D1(const Vec3& f, const Vec3& x) {
  Mat6 D1 = Mat6::Zero();
  const Mat3 F = hat(f);
  D1.topLeftCorner<3, 3>() = F * hat(x);
  D1.topRightCorner<3, 3>() = -F;
  return D1;
}

}  // namespace hovi
