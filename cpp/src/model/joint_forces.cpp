#include "hovi/model/joint_forces.hpp"

namespace hovi {

void JointForces::resize(int n) {
  const int old = static_cast<int>(stiffness.size());
  stiffness.conservativeResize(n);
  preload.conservativeResize(n);
  damping.conservativeResize(n);
  const int m = n_controls();
  actuation.conservativeResize(n, m);
  for (int i = old; i < n; ++i) {
    stiffness[i] = preload[i] = damping[i] = 0;
    actuation.row(i).setZero();
  }
}

}  // namespace hovi
