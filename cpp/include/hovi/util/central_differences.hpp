// The symmetric Hessian of a scalar function by central differences of its exact gradient: the
// second derivatives the DEL equations' Hessian (del_hessian.hpp) and the transcription's holonomic
// rows take this way.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "hovi/spatial/types.hpp"

namespace hovi {

// Central differences' step scale, eps^(1/3): truncation and round-off errors balance.
inline const double kCentralStep = std::cbrt(std::numeric_limits<double>::epsilon());

// H (Z x Z) from gradient(z, g) (g: Z) at z (Z; restored on return), one central difference per
// column j with mask[j] != 0 (step kCentralStep max(1, |z_j|)); symmetrised: an entry of two
// differenced columns is their mean, of one the value that column gives, of none 0 (the caller
// masks only columns whose entries vanish or come by symmetry). gp, gm, D: scratch.
template <class Gradient>
void hessian_by_central_differences(VecX& z, const VecX& mask, Gradient&& gradient, MatX& H, VecX& gp, VecX& gm,
                                    MatX& D) {
  const long Z = z.size();
  D.setZero(Z, Z);
  for (long j = 0; j < Z; ++j) {
    if (mask[j] != 1) continue;
    const double zj = z[j], step = kCentralStep * std::max(1.0, std::abs(zj));
    const double zp = zj + step, zm = zj - step;
    z[j] = zp;
    gradient(z, gp);
    z[j] = zm;
    gradient(z, gm);
    z[j] = zj;
    D.col(j) = (gp - gm) / (zp - zm);
  }
  H = (D + D.transpose()).cwiseProduct(MatX::Ones(Z, Z) - 0.5 * mask * mask.transpose());
}

}  // namespace hovi
