#include "hovi/control/box_qp.hpp"

#include <cmath>
#include <vector>

namespace hovi {
namespace {

MatX take(const MatX& H, const std::vector<int>& rows, const std::vector<int>& cols) {
  MatX out(rows.size(), cols.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < cols.size(); ++j) out(i, j) = H(rows[i], cols[j]);
  return out;
}

}  // namespace

BoxQpResult box_qp(const MatX& H, const VecX& g, const VecX& lower, const VecX& upper, const VecX& x0) {
  const int m = int(g.size());
  BoxQpResult r;
  r.x = x0.cwiseMax(lower).cwiseMin(upper);
  r.free.setConstant(m, true);
  auto value = [&](const VecX& x) { return 0.5 * x.dot(H * x) + g.dot(x); };
  std::vector<int> prev_free;
  for (int it = 0; it < 100; ++it) {
    const VecX grad = g + H * r.x;
    std::vector<int> fr, cl;
    for (int i = 0; i < m; ++i) {
      const bool clamped = (r.x[i] <= lower[i] && grad[i] > 0) || (r.x[i] >= upper[i] && grad[i] < 0);
      r.free[i] = !clamped;
      (clamped ? cl : fr).push_back(i);
    }
    if (fr.empty()) {
      r.llt.compute(MatX(0, 0));
      r.ok = true;
      return r;
    }
    if (it == 0 || fr != prev_free) {
      r.llt.compute(take(H, fr, fr));
      if (r.llt.info() != Eigen::Success) return r;
    }
    prev_free = fr;
    // Newton on the free set with the clamped components fixed
    VecX gf(fr.size()), xf(fr.size());
    for (std::size_t i = 0; i < fr.size(); ++i) {
      gf[i] = grad[fr[i]];
      xf[i] = r.x[fr[i]];
    }
    const VecX step_f = -r.llt.solve(gf);
    VecX search = VecX::Zero(m);
    for (std::size_t i = 0; i < fr.size(); ++i) search[fr[i]] = step_f[i];
    const double slope = search.dot(grad);
    if (!(slope < -1e-14 * (1 + std::abs(value(r.x))))) {
      r.ok = true;
      return r;
    }
    double t = 1, f0 = value(r.x);
    VecX trial;
    bool moved = false;
    for (int ls = 0; ls < 30; ++ls, t *= 0.6) {
      trial = (r.x + t * search).cwiseMax(lower).cwiseMin(upper);
      if (value(trial) - f0 <= 0.1 * (trial - r.x).dot(grad)) {
        moved = true;
        break;
      }
    }
    if (!moved) {
      r.ok = true;
      return r;
    }
    const double change = (trial - r.x).cwiseAbs().maxCoeff();
    r.x = trial;
    if (change <= 1e-14 * (1 + r.x.cwiseAbs().maxCoeff())) break;
  }
  // the final free set's factorisation
  const VecX grad = g + H * r.x;
  std::vector<int> fr;
  for (int i = 0; i < m; ++i) {
    r.free[i] = !((r.x[i] <= lower[i] && grad[i] > 0) || (r.x[i] >= upper[i] && grad[i] < 0));
    if (r.free[i]) fr.push_back(i);
  }
  r.llt.compute(take(H, fr, fr));
  r.ok = fr.empty() || r.llt.info() == Eigen::Success;
  return r;
}

}  // namespace hovi
