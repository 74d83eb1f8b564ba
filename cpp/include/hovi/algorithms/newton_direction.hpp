// Appendix Algorithms A.1 (forward pass) and A.2 (backward pass), with the index ranges of
// docs/paper.md A-1: the exact Newton direction dq = -J^{-1} r of the DEL equations with respect to
// the control points q^{k,1..s}, in O(s^3 n). Index ranges: a, rho in 0..s; gamma, nu in 1..s
// (stored at gamma-1, nu-1); the residual rows a in 0..s-1. Joint armature (del_residual.hpp)
// depends on joint i's own control points only, so it enters the pivot block Λ_i alone.
#pragma once
#include <Eigen/LU>
#include <vector>

#include "hovi/algorithms/del_workspace.hpp"

namespace hovi {

// One of the two families of recursions of Algorithm A.2, the coefficients of a spatial
// variation written in the variations δ̄v̄^rho, η̄^nu and a constant:
//   momentum: δ̄μ̄_i^a = sum_rho D^{a rho} δ̄v̄^rho + sum_nu G^{a nu} η̄^nu + l^a, coupling H^{a gamma};
//   impulse:  δ̄Γ̄_i^a = sum_rho Π^{a rho} δ̄v̄^rho + sum_nu Ψ^{a nu} η̄^nu + ζ^a, coupling Φ^{a gamma}.
// Per body, rows a = 0..s (the impulse family uses rows 0..s-1 only).
struct BlockFamily {
  std::vector<Mat6> Z;   // D or Π: (s+1) x (s+1), columns rho = 0..s
  std::vector<Mat6> ZG;  // G or Ψ: (s+1) x s, columns nu = 1..s
  std::vector<Vec6> z;   // l or ζ: s+1
  std::vector<Vec6> K;   // H or Φ: (s+1) x s, columns gamma = 1..s
  int rows = 0;          // s+1 for momentum, s for impulse
};

struct NewtonWorkspace {
  NewtonWorkspace(const Model& model, const Quadrature& quad);
  int n, s;
  BlockFamily momentum;     // D, G, l, H
  BlockFamily impulse;      // Π, Ψ, ζ, Φ
  std::vector<Vec6> X;      // X_i^{gamma rho} (row vectors): s x (s+1)
  std::vector<Vec6> Y;      // Y_i^{gamma nu}: s x s
  VecX y;                   // y_i^gamma: n x s
  std::vector<Mat6> D1F, D2F;  // D_1F̄_i^a, D_2F̄_i^a of the discrete impulse, a = 0..s-1
  std::vector<MatX> Lambda_inv;     // Λ̄_i = Λ_i^{-1}, s x s per body
  std::vector<Vec6> corr_mu;        // ad^D_{μ̄_i^a} S̄_i^a (0 at a = 0), n x (s+1)
  std::vector<Vec6> corr_Gamma;     // ad^D_{Γ̄_i^a} S̄_i^a (0 at a = 0), n x (s+1)
  // Scratch of one body
  std::vector<Vec6> Theta, Xi;  // Θ̄^{a rho} (s x (s+1)), Ξ̄^{a nu} (s x s), as column vectors
  VecX xi;                      // ξ̄^a
  // Λ_i (s x s) and its factorisation, with storage for s <= 16 (Quadrature's limit) inline:
  // factoring it allocates nothing.
  using PivotBlock = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 16, 16>;
  PivotBlock Lambda;
  Eigen::PartialPivLU<PivotBlock> Lambda_lu;
  // Forward pass
  std::vector<Twist> eta, dv;   // η̄_i^nu (n x s), spatial variation δ̄v̄_i^rho (n x (s+1))
};

// The part of Algorithm A.2 that does not depend on the residual (D, G, Π, Ψ, H, Φ, Λ^{-1}, X,
// Y), O(s^3 n), from the state left in `del` by the last del_residual call. Returns false if a
// pivot block Λ_i is singular (docs/paper.md A-8).
bool newton_factor(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws);

// dq = -J^{-1} r for any right-hand side r (n x s) after newton_factor: the residual-dependent
// recursion of A.2 (l, ζ, ξ̄, y) and Algorithm A.1, O(s^2 n) per right-hand side.
void newton_solve(const Model& model, const Quadrature& quad, const DelWorkspace& del, NewtonWorkspace& ws,
                  const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq);

// newton_factor then newton_solve: dq (n x s, column gamma-1 = δq^{k,gamma}) for the residual r
// of the last del_residual call. Returns false (dq unspecified) if a pivot block is singular.
bool newton_direction(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws,
                      const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq);

}  // namespace hovi
