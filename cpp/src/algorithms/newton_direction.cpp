#include "hovi/algorithms/newton_direction.hpp"

#include <Eigen/LU>

namespace hovi {

NewtonWorkspace::NewtonWorkspace(const Model& model, const Quadrature& quad) : n(model.n()), s(quad.s) {
  const std::size_t N = n, S = s, S1 = s + 1;
  D.resize(N * S1 * S1);
  G.resize(N * S1 * S);
  l.resize(N * S1);
  Pi.resize(N * S * S1);
  Psi.resize(N * S * S);
  zeta.resize(N * S);
  H.resize(N * S1 * S);
  Phi.resize(N * S * S);
  X.resize(N * S * S1);
  Y.resize(N * S * S);
  y.resize(N * S);
  D1F.resize(N * S);
  D2F.resize(N * S);
  Theta.resize(S * S1);
  Xi.resize(S * S);
  xi.resize(S);
  Lambda.resize(S, S);
  eta.resize(N * S);
  dv.resize(N * S1);
}

namespace {

// Derivatives of the discrete impulse F̄_i^a = w^a dt F̄_i (ERRATA C-6), a = 0..s-1.
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

}  // namespace

bool newton_direction(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws,
                      const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq) {
  const int n = model.n(), s = quad.s, S1 = s + 1;
  const double dt = del.dt, idt = 1.0 / dt;
  const MatX& b = quad.b;
  const MatX& A = quad.a;
  // Index maps of the per-body blocks.
  auto iD = [&](int i, int a, int rho) { return (i * S1 + a) * S1 + rho; };
  auto iG = [&](int i, int a, int nu) { return (i * S1 + a) * s + (nu - 1); };   // also H (gamma)
  auto iP = [&](int i, int a, int rho) { return (i * s + a) * S1 + rho; };       // Π, X (gamma-1, rho)
  auto iS = [&](int i, int a, int nu) { return (i * s + a) * s + (nu - 1); };    // Ψ, Φ, Y (gamma-1, nu)

  for (int k = 0; k < n * S1; ++k) del.Sdot[k] = ad(del.v[k], del.Sbar[k]);  // Ṡ̄ = ad_{v̄} S̄
  force_derivatives(model, quad, del, ws);
  const JointForces& jf = model.joint_forces;

  // Own terms of every body (children are added as they finish, below).
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < S1; ++a) {
      for (int rho = 0; rho < S1; ++rho)
        ws.D[iD(i, a, rho)] = a == rho ? del.Mbar[del.at(i, a)].matrix() : Mat6::Zero();
      for (int nu = 1; nu <= s; ++nu) ws.G[iG(i, a, nu)].setZero();
      ws.l[i * S1 + a].setZero();
    }
    for (int a = 0; a < s; ++a) {
      for (int rho = 0; rho < S1; ++rho) ws.Pi[iP(i, a, rho)] = a == rho ? ws.D2F[i * s + a] : Mat6::Zero();
      for (int nu = 1; nu <= s; ++nu) {
        Mat6& P = ws.Psi[iS(i, a, nu)];
        if (a == nu) {
          const int k = del.at(i, a);
          P = ws.D1F[i * s + a] + adD(del.F[k]) - ws.D2F[i * s + a] * ad(del.v[k]);
        } else {
          P.setZero();
        }
      }
      ws.zeta[i * s + a].setZero();
    }
  }

  // Algorithm A.2: backward pass.
  for (int i = n - 1; i >= 0; --i) {
    auto Sb = [&](int a) -> const Twist& { return del.Sbar[del.at(i, a)]; };
    auto Sd = [&](int a) -> const Twist& { return del.Sdot[del.at(i, a)]; };
    // H^{a gamma} and Φ^{a gamma}
    for (int gam = 1; gam <= s; ++gam) {
      for (int a = 0; a < S1; ++a) {
        Vec6 h = ws.D[iD(i, a, gam)] * Sd(gam) + ws.G[iG(i, a, gam)] * Sb(gam);
        for (int rho = 0; rho < S1; ++rho)
          if (b(rho, gam) != 0) h += (idt * b(rho, gam)) * (ws.D[iD(i, a, rho)] * Sb(rho));
        ws.H[iG(i, a, gam)] = h;
      }
      for (int a = 0; a < s; ++a) {
        Vec6 f = ws.Pi[iP(i, a, gam)] * Sd(gam) + ws.Psi[iS(i, a, gam)] * Sb(gam);
        for (int rho = 0; rho < S1; ++rho)
          if (b(rho, gam) != 0) f += (idt * b(rho, gam)) * (ws.Pi[iP(i, a, rho)] * Sb(rho));
        ws.Phi[iS(i, a, gam)] = f;
      }
    }
    // Θ̄, Ξ̄, ξ̄ and Λ for the residual rows a = 0..s-1.
    for (int a = 0; a < s; ++a) {
      const int ka = del.at(i, a);
      const double wdt = quad.w[a] * dt;
      const Mat6 adDmu = adD(del.mu[ka]);
      for (int rho = 0; rho < S1; ++rho) {
        Vec6 th = wdt * (ws.D[iD(i, a, rho)].transpose() * Sd(a)) + ws.Pi[iP(i, a, rho)].transpose() * Sb(a);
        if (rho == a) th += wdt * (adDmu.transpose() * Sb(a));
        for (int be = 0; be < S1; ++be) th += A(a, be) * (ws.D[iD(i, be, rho)].transpose() * Sb(be));
        ws.Theta[a * S1 + rho] = th;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Vec6 x = wdt * (ws.G[iG(i, a, nu)].transpose() * Sd(a)) + ws.Psi[iS(i, a, nu)].transpose() * Sb(a);
        for (int be = 0; be < S1; ++be) x += A(a, be) * (ws.G[iG(i, be, nu)].transpose() * Sb(be));
        ws.Xi[a * s + nu - 1] = x;
      }
      double x = wdt * Sd(a).dot(ws.l[i * S1 + a]) + Sb(a).dot(ws.zeta[i * s + a]);
      for (int be = 0; be < S1; ++be) x += A(a, be) * Sb(be).dot(ws.l[i * S1 + be]);
      ws.xi[a] = x;
      for (int gam = 1; gam <= s; ++gam) {
        double L = wdt * Sd(a).dot(ws.H[iG(i, a, gam)]) + Sb(a).dot(ws.Phi[iS(i, a, gam)]);
        for (int be = 0; be < S1; ++be) L += A(a, be) * Sb(be).dot(ws.H[iG(i, be, gam)]);
        if (a == gam) L += wdt * (-jf.stiffness[i] + Sb(a).dot(adDmu * Sd(a)));  // D_1Q + ...
        L += idt * b(a, gam) * wdt * (-jf.damping[i]);                               // (1/dt) b D_2Q
        ws.Lambda(a, gam - 1) = L;
      }
    }
    // X, Y, y = -Λ^{-1} (Θ̄, Ξ̄, r + ξ̄)
    const Eigen::PartialPivLU<MatX> lu(ws.Lambda);
    const double scale = ws.Lambda.cwiseAbs().maxCoeff();
    if (!(std::abs(lu.determinant()) > 0) || !(scale > 0) ||
        lu.matrixLU().diagonal().cwiseAbs().minCoeff() <= 1e-14 * scale)
      return false;
    const MatX Linv = lu.inverse();
    for (int gam = 1; gam <= s; ++gam) {
      for (int rho = 0; rho < S1; ++rho) {
        Vec6 x = Vec6::Zero();
        for (int v = 0; v < s; ++v) x -= Linv(gam - 1, v) * ws.Theta[v * S1 + rho];
        ws.X[iP(i, gam - 1, rho)] = x;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Vec6 x = Vec6::Zero();
        for (int v = 0; v < s; ++v) x -= Linv(gam - 1, v) * ws.Xi[v * s + nu - 1];
        ws.Y[iS(i, gam - 1, nu)] = x;
      }
      double yy = 0;
      for (int v = 0; v < s; ++v) yy -= Linv(gam - 1, v) * (r(i, v) + ws.xi[v]);
      ws.y[i * s + gam - 1] = yy;
    }
    // Contributions of body i to its parent (A.2 sums over chd(par)); X^{0 rho} = 0 etc.
    const int p = model.parent[i];
    if (p < 0) continue;
    for (int a = 0; a < S1; ++a) {
      const int ka = del.at(i, a);
      const Vec6 adS = a >= 1 ? Vec6(adD(del.mu[ka]) * Sb(a)) : Vec6::Zero();
      for (int rho = 0; rho < S1; ++rho) {
        Mat6 acc = ws.D[iD(i, a, rho)];
        for (int gam = 1; gam <= s; ++gam) acc.noalias() += ws.H[iG(i, a, gam)] * ws.X[iP(i, gam - 1, rho)].transpose();
        if (a >= 1) acc.noalias() -= adS * ws.X[iP(i, a - 1, rho)].transpose();
        ws.D[iD(p, a, rho)] += acc;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Mat6 acc = ws.G[iG(i, a, nu)];
        for (int gam = 1; gam <= s; ++gam) acc.noalias() += ws.H[iG(i, a, gam)] * ws.Y[iS(i, gam - 1, nu)].transpose();
        if (a >= 1) acc.noalias() -= adS * ws.Y[iS(i, a - 1, nu)].transpose();
        ws.G[iG(p, a, nu)] += acc;
      }
      Vec6 acc = ws.l[i * S1 + a];
      for (int gam = 1; gam <= s; ++gam) acc += ws.H[iG(i, a, gam)] * ws.y[i * s + gam - 1];
      if (a >= 1) acc -= adS * ws.y[i * s + a - 1];
      ws.l[p * S1 + a] += acc;
    }
    for (int a = 0; a < s; ++a) {
      const int ka = del.at(i, a);
      const Vec6 adG = a >= 1 ? Vec6(adD(del.Gamma[ka]) * Sb(a)) : Vec6::Zero();
      for (int rho = 0; rho < S1; ++rho) {
        Mat6 acc = ws.Pi[iP(i, a, rho)];
        for (int gam = 1; gam <= s; ++gam) acc.noalias() += ws.Phi[iS(i, a, gam)] * ws.X[iP(i, gam - 1, rho)].transpose();
        if (a >= 1) acc.noalias() -= adG * ws.X[iP(i, a - 1, rho)].transpose();
        ws.Pi[iP(p, a, rho)] += acc;
      }
      for (int nu = 1; nu <= s; ++nu) {
        Mat6 acc = ws.Psi[iS(i, a, nu)];
        for (int gam = 1; gam <= s; ++gam) acc.noalias() += ws.Phi[iS(i, a, gam)] * ws.Y[iS(i, gam - 1, nu)].transpose();
        if (a >= 1) acc.noalias() -= adG * ws.Y[iS(i, a - 1, nu)].transpose();
        ws.Psi[iS(p, a, nu)] += acc;
      }
      Vec6 acc = ws.zeta[i * s + a];
      for (int gam = 1; gam <= s; ++gam) acc += ws.Phi[iS(i, a, gam)] * ws.y[i * s + gam - 1];
      if (a >= 1) acc -= adG * ws.y[i * s + a - 1];
      ws.zeta[p * s + a] += acc;
    }
  }

  // Algorithm A.1: forward pass.
  for (int i = 0; i < n; ++i) {
    const int p = model.parent[i];
    for (int gam = 1; gam <= s; ++gam) {
      double d = ws.y[i * s + gam - 1];
      if (p >= 0) {
        for (int rho = 0; rho < S1; ++rho) d += ws.X[iP(i, gam - 1, rho)].dot(ws.dv[p * S1 + rho]);
        for (int nu = 1; nu <= s; ++nu) d += ws.Y[iS(i, gam - 1, nu)].dot(ws.eta[p * s + nu - 1]);
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
  return true;
}

}  // namespace hovi
