#include "hovi/model/visual.hpp"

#include "hovi/errors.hpp"

namespace hovi {

void check_visual(const Visual& v, int n_bodies) {
  const std::string what = "visual of '" + (v.link.empty() ? std::string("body ") + std::to_string(v.body) : v.link) + "'";
  if (v.body < -1 || v.body >= n_bodies)
    throw ModelError(what + ": body index " + std::to_string(v.body) + " does not name a body (or -1, the world)");
  if (!v.size.allFinite() || !v.scale.allFinite() || !v.origin.R.allFinite() || !v.origin.p.allFinite())
    throw ModelError(what + ": non-finite size, scale or origin");
  const Mat3& R = v.origin.R;
  if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-9 || R.determinant() < 0)
    throw ModelError(what + ": origin rotation is not a rotation matrix");
  const int positive = v.shape == VisualShape::Box ? 3 : v.shape == VisualShape::Cylinder ? 2 : v.shape == VisualShape::Sphere ? 1 : 0;
  for (int k = 0; k < positive; ++k)
    if (!(v.size[k] > 0)) throw ModelError(what + ": sizes must be positive");
  if (v.shape == VisualShape::Mesh && v.filename.empty()) throw ModelError(what + ": mesh without a filename");
  if (v.rgba && (!v.rgba->allFinite() || v.rgba->minCoeff() < 0 || v.rgba->maxCoeff() > 1))
    throw ModelError(what + ": rgba must be four numbers in [0, 1]");
}

}  // namespace hovi
