// Joint forces Q_i(q_i, q̇_i, u) (paper Assumption 1): linear springs, linear dampers and
// control inputs through an actuation map,
//   Q_i = -k_i (q_i - qref_i) - c_i q̇_i + (B u)_i,
// with D_1Q_i = -k_i, D_2Q_i = -c_i and dQ/du = B.
#pragma once
#include "hovi/spatial/types.hpp"

namespace hovi {

struct JointForces {
  VecX stiffness;   // k_i (sum of the springs on joint i)
  VecX preload;     // k_i qref_i (sum over the springs on joint i)
  VecX damping;     // c_i
  MatX actuation;   // B, n x m: Q += B u

  void resize(int n);  // keeps existing entries, new joints get none
  int n_controls() const { return static_cast<int>(actuation.cols()); }
  bool has_springs() const { return stiffness.size() && stiffness.cwiseAbs().maxCoeff() > 0; }
  bool has_dampers() const { return damping.size() && damping.cwiseAbs().maxCoeff() > 0; }
  bool any() const { return has_springs() || has_dampers() || n_controls() > 0; }
};

}  // namespace hovi
