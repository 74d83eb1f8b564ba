#include "hovi/control/shooting_problem.hpp"

#include <cmath>
#include <string>

#include "hovi/errors.hpp"

namespace hovi {
namespace {

void check_cost(const SampleCost& c, int rows_unit, int n, int m, std::size_t i) {
  const std::string at = "cost term " + std::to_string(i);
  const long rows = c.Wq.rows();
  if (rows < 1 || (c.terminal ? rows != 1 : rows % rows_unit != 0))
    throw InputError(at + ": " + (c.terminal ? "a terminal term has one sample" : "a running term has S (s+1) samples"));
  auto check = [&](const MatX& M, long cols, const char* name, bool weight) {
    if (M.rows() != rows || M.cols() != cols)
      throw InputError(at + ": " + name + " must be (" + std::to_string(rows) + ", " + std::to_string(cols) + ")");
    if (!M.allFinite()) throw InputError(at + ": " + name + " holds NaN or infinity");
    if (weight && M.size() && M.minCoeff() < 0) throw InputError(at + ": " + name + " has a negative weight");
  };
  check(c.Wq, n, "Wq", true);
  check(c.q_ref, n, "q_ref", false);
  check(c.Wv, n, "Wv", true);
  check(c.v_ref, n, "v_ref", false);
  check(c.R, m, "R", true);
  check(c.u_ref, m, "u_ref", false);
}

}  // namespace

ShootingProblem::ShootingProblem(const GalerkinIntegrator& integ, int N, const VecX& x0, std::vector<SampleCost> costs,
                                 const VecX& u_lower, const VecX& u_upper, double smoothing)
    : integ_(integ),
      lin_(integ),
      smoothing_(smoothing),
      N_(N),
      n_(integ.model().n()),
      m_(integ.model().n_controls()),
      s_(integ.quadrature().s),
      lo_(u_lower),
      hi_(u_upper),
      costs_(std::move(costs)) {
  if (integ.model().n_constraints()) throw InputError("shooting on a model with holonomic constraints is not supported");
  if (N < 1) throw InputError("the horizon needs at least one step");
  if (m_ < 1) throw InputError("the model has no controls");
  set_x0(x0);
  if (lo_.size() != m_ || hi_.size() != m_ || lo_.hasNaN() || hi_.hasNaN() || (lo_.array() > hi_.array()).any())
    throw InputError("control bounds must be m numbers with lower <= upper");
  for (std::size_t i = 0; i < costs_.size(); ++i) check_cost(costs_[i], s_ + 1, n_, m_, i);
  if (integ.has_contacts() && (s_ != 1 || integ.contact_options().locate_impacts))
    throw InputError("shooting through contact needs s = 1 without impact location (the trajectory optimiser's "
                     "time-stepping: a step split at an impact is not differentiable)");
  if (!(smoothing >= 0) || !std::isfinite(smoothing)) throw InputError("smoothing must be finite and >= 0");
  if (smoothing > 0 && !integ.has_contacts()) throw InputError("smoothing is for shooting through contact");
}

void ShootingProblem::set_x0(const VecX& x0) {
  if (x0.size() != 2 * n_ || !x0.allFinite()) throw InputError("x0 must be 2n finite numbers (q, p)");
  x0_ = x0;
}

bool ShootingProblem::step(const VecX& x, const VecX& u, VecX& x_next, MatX& qc, bool guessed, VecX& z) const {
  const int S1 = s_ + 1;
  const MatX uk = u.replicate(1, S1);
  qc.resize(n_, S1);
  qc.col(0) = x.head(n_);
  VecX p_next(n_);
  SolveInfo info;
  // A guess (the free step's control points of an earlier iterate) first; else, or if it fails, every
  // stage of the step from q^k (through contact: from the impulses z of an earlier iterate).
  if (guessed && !has_contacts()) info = integ_.solve(x.tail(n_), uk, qc, p_next);
  if (!guessed || has_contacts() || !info.converged()) {
    qc.rightCols(s_) = x.head(n_).replicate(1, s_);
    StepHistory h;
    if (z.size() == impulses()) h.z = z;
    info = integ_.step(x.tail(n_), uk, qc, p_next, h);
    z = h.z;
  }
  if (!info.converged()) return false;
  x_next.resize(2 * n_);
  x_next << qc.col(s_), p_next;
  return true;
}

void ShootingProblem::point_cost(int k, const MatX& qc, const VecX& u, double* value, MatX* g, MatX* H, VecX* gu,
                                 MatX* Huu) const {
  const int S1 = s_ + 1, n = n_;
  const MatX& b = integ_.quadrature().b;
  const double dt = integ_.dt();
  const MatX V = qc * b.transpose() / dt;  // column a: q̇^{k,a}
  if (value) *value = 0;
  if (g) g->setZero(n, S1);
  if (H) H->setZero(S1 * n, S1 * n);
  if (gu) gu->setZero(m_);
  if (Huu) Huu->setZero(m_, m_);
  for (const SampleCost& c : costs_) {
    for (int a = 0; a < S1; ++a) {
      int row;
      if (c.terminal) {
        if (k != N_ - 1 || a != s_) continue;
        row = 0;
      } else {
        row = std::min(offset + k, int(c.Wq.rows() / S1) - 1) * S1 + a;
      }
      const auto Wq = c.Wq.row(row).transpose(), Wv = c.Wv.row(row).transpose(), R = c.R.row(row).transpose();
      const VecX eq = qc.col(a) - c.q_ref.row(row).transpose(), ev = V.col(a) - c.v_ref.row(row).transpose();
      const VecX eu = u - c.u_ref.row(row).transpose();
      if (value) *value += eq.dot(Wq.cwiseProduct(eq)) + ev.dot(Wv.cwiseProduct(ev)) + eu.dot(R.cwiseProduct(eu));
      if (g) {
        g->col(a) += 2 * Wq.cwiseProduct(eq);
        const VecX gv = 2 * Wv.cwiseProduct(ev) / dt;  // d/dq^{k,c} of |q̇^a - v_ref|^2 = b^{ac} / dt
        for (int cc = 0; cc < S1; ++cc) g->col(cc) += b(a, cc) * gv;
      }
      if (H) {
        H->block(a * n, a * n, n, n).diagonal() += 2 * Wq;
        const VecX hv = 2 * Wv / (dt * dt);
        for (int r = 0; r < S1; ++r)
          for (int cc = 0; cc < S1; ++cc) H->block(r * n, cc * n, n, n).diagonal() += b(a, r) * b(a, cc) * hv;
      }
      if (gu) *gu += 2 * R.cwiseProduct(eu);
      if (Huu) Huu->diagonal() += 2 * R;
    }
  }
}

double ShootingProblem::stage_cost(int k, const MatX& qc, const VecX& u) const {
  double v = 0;
  point_cost(k, qc, u, &v, nullptr, nullptr, nullptr, nullptr);
  return v;
}

bool ShootingProblem::derivatives(int k, const MatX& qc, const VecX& u, const VecX& z, StageDerivatives& d,
                                  const VecX* extra_g, const MatX* extra_H) const {
  const int S1 = s_ + 1, n = n_, m = m_, sn = s_ * n;
  const MatX uk = u.replicate(1, S1);
  MatX Bp, Yx, Yu;
  const MatX w = has_contacts() ? MatX(z) : MatX();  // the step's impulses (through contact)
  if (!lin_.step_jacobians(qc, uk, &d.A, &Bp, w, &Yx, &Yu, smoothing_)) return false;
  d.B = MatX::Zero(2 * n, m);
  MatX Yuh = MatX::Zero(sn, m);
  for (int a = 0; a < S1; ++a) {  // held controls: the sum over the control points' blocks
    d.B += Bp.middleCols(a * m, m);
    Yuh += Yu.middleCols(a * m, m);
  }
  // dQ/dx and dQ/du with Q = vec(q^{k,0..s}): q^{k,0} = q^k, then y = q^{k,1..s}
  MatX Qx = MatX::Zero(S1 * n, 2 * n), Qu = MatX::Zero(S1 * n, m);
  Qx.topLeftCorner(n, n).setIdentity();
  Qx.bottomRows(sn) = Yx;
  Qu.bottomRows(sn) = Yuh;
  MatX g, H, Huu;
  VecX gu;
  point_cost(k, qc, u, nullptr, &g, &H, &gu, &Huu);
  if (extra_g) {  // z = (vec Q, u): its Q-blocks join the built-in terms', its u-blocks act directly
    const int nQ = S1 * n;
    Eigen::Map<VecX>(g.data(), g.size()) += extra_g->head(nQ);
    gu += extra_g->tail(m);
    H += extra_H->topLeftCorner(nQ, nQ);
    Huu += extra_H->bottomRightCorner(m, m);
  }
  const Eigen::Map<const VecX> gv(g.data(), g.size());
  const MatX HQx = H * Qx;
  d.lx = Qx.transpose() * gv;
  d.lu = Qu.transpose() * gv + gu;
  d.lxx = Qx.transpose() * HQx;
  d.lux = Qu.transpose() * HQx;
  d.luu = Qu.transpose() * H * Qu + Huu;
  if (extra_H) {  // the cross terms u-Q of the outside cost: d2/du dQ through Q(x, u)
    const int nQ = S1 * n;
    const MatX HuQ = extra_H->bottomLeftCorner(m, nQ);
    d.lux += HuQ * Qx;
    const MatX HuQ_Qu = HuQ * Qu;
    d.luu += HuQ_Qu + HuQ_Qu.transpose();
  }
  return true;
}

}  // namespace hovi
