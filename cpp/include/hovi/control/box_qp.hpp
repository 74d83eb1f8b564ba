// min 1/2 x^T H x + g^T x subject to lower <= x <= upper, by projected Newton (Bertsekas 1982, as
// Tassa, Mansard and Todorov 2014 use it for control-limited DDP): Newton on the free set, a
// projected Armijo line search, until the free set and the clamped gradient settle.
#pragma once
#include <Eigen/Cholesky>

#include "hovi/spatial/types.hpp"

namespace hovi {

struct BoxQpResult {
  VecX x;
  Eigen::Matrix<bool, Eigen::Dynamic, 1> free;  // components not held at a bound
  Eigen::LLT<MatX> llt;                         // of H on the free set (the DDP gains need it)
  bool ok = false;                              // false: H not positive definite on the free set
};

// x0: the warm start (clamped first).
BoxQpResult box_qp(const MatX& H, const VecX& g, const VecX& lower, const VecX& upper, const VecX& x0);

}  // namespace hovi
