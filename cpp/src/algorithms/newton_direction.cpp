#include "hovi/algorithms/newton_direction.hpp"

#include <Eigen/LU>

namespace hovi {

namespace {

void resize(BlockFamily& f, int n, int s, int rows) {
  const std::size_t N = n, S = s, S1 = s + 1;
  f.Z.resize(N * S1 * S1);
  f.ZG.resize(N * S1 * S);
  f.z.resize(N * S1);
  f.K.resize(N * S1 * S);
  f.rows = rows;
}

}  // namespace

NewtonWorkspace::NewtonWorkspace(const Model& model, const Quadrature& quad) : n(model.n()), s(quad.s) {
  const std::size_t N = n, S = s, S1 = s + 1;
  resize(momentum, n, s, s + 1);
  resize(impulse, n, s, s);
  X.resize(N * S * S1);
  Y.resize(N * S * S);
  y.resize(N * S);
  D1F.resize(N * S);
  D2F.resize(N * S);
  Theta.resize(S * S1);
  Xi.resize(S * S);
  xi.resize(S);
  Lambda.resize(S, S);
  Lambda_lu = Eigen::PartialPivLU<PivotBlock>(s);
  Lambda_inv.assign(N, MatX(S, S));
  corr_mu.resize(N * S1);
  corr_Gamma.resize(N * S1);
  eta.resize(N * S);
  dv.resize(N * S1);
}

namespace {

// Derivatives of the discrete impulse F̄_i^a = w^a dt F̄_i (docs/paper.md C-6), a = 0..s-1.
void force_derivatives(const Model& model, const Quadrature& quad, const DelWorkspace& del, NewtonWorkspace& ws) {
  const int s = quad.s;
  const bool gravity = model.has_gravity();
  for (int i = 0; i < model.n(); ++i)
    for (int a = 0; a < s; ++a) {
      const int k = del.at(i, a);
      Mat6& D1 = ws.D1F[i * s + a];
      Mat6& D2 = ws.D2F[i * s + a];
      D1.setZero();
      D2.setZero();
      if (gravity) D1 = world_force_D1(model.M[i].m * model.gravity, del.g[k].p);
      for (const BodyWrench* w : del.wrenches[i]) w->add_derivatives(del.g[k], del.v[k], del.u.col(a), D1, D2);
      const double wdt = quad.w[a] * del.dt;
      D1 *= wdt;
      D2 *= wdt;
    }
}

// Index maps of the per-body blocks (body i, row a, column rho in 0..s or nu/gamma in 1..s).
struct Index {
  int s, S1;
  int Z(int i, int a, int rho) const { return (i * S1 + a) * S1 + rho; }
  int G(int i, int a, int nu) const { return (i * S1 + a) * s + (nu - 1); }  // ZG and K
  int z(int i, int a) const { return i * S1 + a; }
  int X(int i, int gam, int rho) const { return (i * s + gam - 1) * S1 + rho; }
  int Y(int i, int gam, int nu) const { return (i * s + gam - 1) * s + (nu - 1); }
};

// K^{a gamma} = Z^{a gamma} Ṡ̄^gamma + ZG^{a gamma} S̄^gamma + (1/dt) sum_rho b^{rho gamma} Z^{a rho} S̄^rho
// (A.2 lines 3 and 4: H from D, G and Φ from Π, Ψ).
void couple(BlockFamily& f, const Index& ix, int i, const DelWorkspace& del, const MatX& b, double idt) {
  for (int gam = 1; gam <= ix.s; ++gam)
    for (int a = 0; a < f.rows; ++a) {
      Vec6 k = f.Z[ix.Z(i, a, gam)] * del.Sdot[del.at(i, gam)] + f.ZG[ix.G(i, a, gam)] * del.Sbar[del.at(i, gam)];
      for (int rho = 0; rho < ix.S1; ++rho)
        if (b(rho, gam) != 0) k += (idt * b(rho, gam)) * (f.Z[ix.Z(i, a, rho)] * del.Sbar[del.at(i, rho)]);
      f.K[ix.G(i, a, gam)] = k;
    }
}

// Body i's share of its parent's sums over chd (A.2 lines 1 and 2), with X^{0 rho} = Y^{0 nu} =
// y^0 = 0 (docs/paper.md A-6):  Z_p^{a rho} += Z_i^{a rho} + sum_gamma K_i^{a gamma} X_i^{gamma rho}
// - corr^a X_i^{a rho}, and likewise ZG with Y; corr^a = ad^D_{μ̄ or Γ̄} S̄ (0 at a = 0).
void propagate_blocks(BlockFamily& f, const Index& ix, int i, int p, const NewtonWorkspace& ws,
                      const std::vector<Vec6>& corr) {
  const int s = ix.s;
  for (int a = 0; a < f.rows; ++a) {
    const Vec6& c = corr[ix.z(i, a)];
    for (int rho = 0; rho < ix.S1; ++rho) {
      Mat6 acc = f.Z[ix.Z(i, a, rho)];
      for (int gam = 1; gam <= s; ++gam) acc.noalias() += f.K[ix.G(i, a, gam)] * ws.X[ix.X(i, gam, rho)].transpose();
      if (a >= 1) acc.noalias() -= c * ws.X[ix.X(i, a, rho)].transpose();
      f.Z[ix.Z(p, a, rho)] += acc;
    }
    for (int nu = 1; nu <= s; ++nu) {
      Mat6 acc = f.ZG[ix.G(i, a, nu)];
      for (int gam = 1; gam <= s; ++gam) acc.noalias() += f.K[ix.G(i, a, gam)] * ws.Y[ix.Y(i, gam, nu)].transpose();
      if (a >= 1) acc.noalias() -= c * ws.Y[ix.Y(i, a, nu)].transpose();
      f.ZG[ix.G(p, a, nu)] += acc;
    }
  }
}

// The same for the offsets: z_p^a += z_i^a + sum_gamma K_i^{a gamma} y_i^gamma - corr^a y_i^a.
void propagate_offsets(BlockFamily& f, const Index& ix, int i, int p, const NewtonWorkspace& ws,
                       const std::vector<Vec6>& corr) {
  const int s = ix.s;
  for (int a = 0; a < f.rows; ++a) {
    Vec6 acc = f.z[ix.z(i, a)];
    for (int gam = 1; gam <= s; ++gam) acc += f.K[ix.G(i, a, gam)] * ws.y[i * s + gam - 1];
    if (a >= 1) acc -= corr[ix.z(i, a)] * ws.y[i * s + a - 1];
    f.z[ix.z(p, a)] += acc;
  }
}

}  // namespace

bool newton_factor(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws) {
  const int n = model.n(), s = quad.s, S1 = s + 1;
  const double dt = del.dt, idt = 1.0 / dt;
  const MatX& b = quad.b;
  const MatX& A = quad.a;
  const Index ix{s, S1};
  BlockFamily& mom = ws.momentum;  // D, G, H
  BlockFamily& imp = ws.impulse;   // Π, Ψ, Φ

  for (int k = 0; k < n * S1; ++k) del.Sdot[k] = ad(del.v[k], del.Sbar[k]);  // Ṡ̄ = ad_{v̄} S̄
  force_derivatives(model, quad, del, ws);
  const JointForces& jf = model.joint_forces;
  const bool armature = model.has_armature();

  // Own terms of every body (children are added as they finish, below).
  for (int i = 0; i < n; ++i)
    for (int a = 0; a < S1; ++a) {
      const int k = del.at(i, a);
      for (int rho = 0; rho < S1; ++rho) {
        mom.Z[ix.Z(i, a, rho)] = a == rho ? del.Mbar[k].matrix() : Mat6::Zero();  // σ M̄
        imp.Z[ix.Z(i, a, rho)] = a == rho && a < s ? ws.D2F[i * s + a] : Mat6::Zero();  // σ D_2F̄
      }
      for (int nu = 1; nu <= s; ++nu) {
        mom.ZG[ix.G(i, a, nu)].setZero();
        if (a == nu && a < s)  // σ (D_1F̄ + ad^D_F̄ - D_2F̄ ad_v̄), docs/paper.md A-3
          imp.ZG[ix.G(i, a, nu)] = ws.D1F[i * s + a] + adD(del.F[k]) - ws.D2F[i * s + a] * ad(del.v[k]);
        else
          imp.ZG[ix.G(i, a, nu)].setZero();
      }
      ws.corr_mu[ix.z(i, a)] = a >= 1 ? Vec6(adD(del.mu[k]) * del.Sbar[k]) : Vec6::Zero();
      ws.corr_Gamma[ix.z(i, a)] = a >= 1 ? Vec6(adD(del.Gamma[k]) * del.Sbar[k]) : Vec6::Zero();
    }

  // Algorithm A.2, backward pass: the residual-independent part.
  for (int i = n - 1; i >= 0; --i) {
    auto Sb = [&](int a) -> const Twist& { return del.Sbar[del.at(i, a)]; };
    auto Sd = [&](int a) -> const Twist& { return del.Sdot[del.at(i, a)]; };
    couple(mom, ix, i, del, b, idt);  // H
    couple(imp, ix, i, del, b, idt);  // Φ
    // Θ̄, Ξ̄ and Λ for the residual rows a = 0..s-1.
    for (int a = 0; a < s; ++a) {
      const double wdt = quad.w[a] * dt;
      const Mat6 adDmu = adD(del.mu[del.at(i, a)]);
      for (int rho = 0; rho < S1; ++rho) {
        Vec6 th = wdt * (mom.Z[ix.Z(i, a, rho)].transpose() * Sd(a)) + imp.Z[ix.Z(i, a, rho)].transpose() * Sb(a);
        if (rho == a) th += wdt * (adDmu.transpose() * Sb(a));
        for (int be = 0; be < S1; ++be) th += A(a, be) * (mom.Z[ix.Z(i, be, rho)].transpose() * Sb(be));
        ws.Theta[a * S1 + rho] = th;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Vec6 x = wdt * (mom.ZG[ix.G(i, a, nu)].transpose() * Sd(a)) + imp.ZG[ix.G(i, a, nu)].transpose() * Sb(a);
        for (int be = 0; be < S1; ++be) x += A(a, be) * (mom.ZG[ix.G(i, be, nu)].transpose() * Sb(be));
        ws.Xi[a * s + nu - 1] = x;
      }
      for (int gam = 1; gam <= s; ++gam) {
        double L = wdt * Sd(a).dot(mom.K[ix.G(i, a, gam)]) + Sb(a).dot(imp.K[ix.G(i, a, gam)]);
        for (int be = 0; be < S1; ++be) L += A(a, be) * Sb(be).dot(mom.K[ix.G(i, be, gam)]);
        if (a == gam) L += wdt * (-jf.stiffness[i] + Sb(a).dot(adDmu * Sd(a)));  // D_1Q + w dt S̄ ad^D_μ̄ Ṡ̄
        L += idt * b(a, gam) * wdt * (-jf.damping[i]);                               // (1/dt) b D_2Q
        if (armature) {  // d/dq_i^gam of sum_be a^{a be} a_i q̇_i^be, q̇^be = (1/dt) sum_c b^{be c} q^c
          double Ab = 0;
          for (int be = 0; be < S1; ++be) Ab += A(a, be) * b(be, gam);
          L += idt * model.armature[i] * Ab;
        }
        ws.Lambda(a, gam - 1) = L;
      }
    }
    // Λ̄ = Λ^{-1}; X, Y = -Λ̄ (Θ̄, Ξ̄)
    const auto& lu = ws.Lambda_lu.compute(ws.Lambda);
    const double scale = ws.Lambda.cwiseAbs().maxCoeff();
    if (!(scale > 0) || !(lu.matrixLU().diagonal().cwiseAbs().minCoeff() > 1e-14 * scale)) return false;
    MatX& Linv = ws.Lambda_inv[i];
    Linv = lu.inverse();
    for (int gam = 1; gam <= s; ++gam) {
      for (int rho = 0; rho < S1; ++rho) {
        Vec6 x = Vec6::Zero();
        for (int v = 0; v < s; ++v) x -= Linv(gam - 1, v) * ws.Theta[v * S1 + rho];
        ws.X[ix.X(i, gam, rho)] = x;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Vec6 x = Vec6::Zero();
        for (int v = 0; v < s; ++v) x -= Linv(gam - 1, v) * ws.Xi[v * s + nu - 1];
        ws.Y[ix.Y(i, gam, nu)] = x;
      }
    }
    const int p = model.parent[i];
    if (p < 0) continue;
    propagate_blocks(mom, ix, i, p, ws, ws.corr_mu);
    propagate_blocks(imp, ix, i, p, ws, ws.corr_Gamma);
  }
  return true;
}

void newton_solve(const Model& model, const Quadrature& quad, const DelWorkspace& del, NewtonWorkspace& ws,
                  const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  const int n = model.n(), s = quad.s, S1 = s + 1;
  const double dt = del.dt, idt = 1.0 / dt;
  const MatX& b = quad.b;
  const MatX& A = quad.a;
  const Index ix{s, S1};
  BlockFamily& mom = ws.momentum;  // l
  BlockFamily& imp = ws.impulse;   // ζ
  for (int k = 0; k < n * S1; ++k) {
    mom.z[k].setZero();
    imp.z[k].setZero();
  }
  // Algorithm A.2, backward pass: l, ζ, ξ̄ and y = -Λ̄ (r + ξ̄).
  for (int i = n - 1; i >= 0; --i) {
    auto Sb = [&](int a) -> const Twist& { return del.Sbar[del.at(i, a)]; };
    for (int a = 0; a < s; ++a) {
      double x = quad.w[a] * dt * del.Sdot[del.at(i, a)].dot(mom.z[ix.z(i, a)]) + Sb(a).dot(imp.z[ix.z(i, a)]);
      for (int be = 0; be < S1; ++be) x += A(a, be) * Sb(be).dot(mom.z[ix.z(i, be)]);
      ws.xi[a] = x + r(i, a);
    }
    ws.y.segment(i * s, s).noalias() = -ws.Lambda_inv[i] * ws.xi;
    const int p = model.parent[i];
    if (p < 0) continue;
    propagate_offsets(mom, ix, i, p, ws, ws.corr_mu);
    propagate_offsets(imp, ix, i, p, ws, ws.corr_Gamma);
  }

  // Algorithm A.1: forward pass.
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    for (int gam = 1; gam <= s; ++gam) {
      double d = ws.y[i * s + gam - 1];
      if (p >= 0) {
        for (int rho = 0; rho < S1; ++rho) d += ws.X[ix.X(i, gam, rho)].dot(ws.dv[p * S1 + rho]);
        for (int nu = 1; nu <= s; ++nu) d += ws.Y[ix.Y(i, gam, nu)].dot(ws.eta[p * s + nu - 1]);
      }
      dq(i, gam - 1) = d;
    }
    for (int nu = 1; nu <= s; ++nu) {
      Twist e = del.Sbar[del.at(i, nu)] * dq(i, nu - 1);
      if (p >= 0) e += ws.eta[p * s + nu - 1];
      ws.eta[i * s + nu - 1] = e;
    }
    for (int rho = 0; rho < S1; ++rho) {
      double dqd = 0;
      for (int gam = 1; gam <= s; ++gam) dqd += idt * b(rho, gam) * dq(i, gam - 1);
      Twist dvr = del.Sbar[del.at(i, rho)] * dqd;
      if (rho >= 1) dvr += del.Sdot[del.at(i, rho)] * dq(i, rho - 1);
      if (p >= 0) dvr += ws.dv[p * S1 + rho];
      ws.dv[i * S1 + rho] = dvr;
    }
  }
}

bool newton_direction(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws,
                      const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  if (!newton_factor(model, quad, del, ws)) return false;
  newton_solve(model, quad, del, ws, r, dq);
  return true;
}

}  // namespace hovi
