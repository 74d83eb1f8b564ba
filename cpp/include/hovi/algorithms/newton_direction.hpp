// Appendix Algorithms A.1 (forward pass) and A.2 (backward pass), with the index ranges of
// ERRATA A-1: the exact Newton direction dq = -J^{-1} r of the DEL equations with respect to
// the control points q^{k,1..s}, in O(s^3 n). Index ranges: a, rho in 0..s; gamma, nu in 1..s
// (stored at gamma-1, nu-1); the residual rows a in 0..s-1.
#pragma once
#include <vector>

#include "hovi/algorithms/del_workspace.hpp"

namespace hovi {

struct NewtonWorkspace {
  NewtonWorkspace(const Model& model, const Quadrature& quad);
  int n, s;
  // Per body blocks, row-major in (first index, second index):
  std::vector<Mat6> D;      // D_i^{a rho}: (s+1) x (s+1)
  std::vector<Mat6> G;      // G_i^{a nu}: (s+1) x s
  std::vector<Vec6> l;      // l_i^a: s+1
  std::vector<Mat6> Pi;     // Π_i^{a rho}: s x (s+1)
  std::vector<Mat6> Psi;    // Ψ_i^{a nu}: s x s
  std::vector<Vec6> zeta;   // ζ_i^a: s
  std::vector<Vec6> H;      // H_i^{a gamma}: (s+1) x s
  std::vector<Vec6> Phi;    // Φ_i^{a gamma}: s x s
  std::vector<Vec6> X;      // X_i^{gamma rho} (row vectors): s x (s+1)
  std::vector<Vec6> Y;      // Y_i^{gamma nu}: s x s
  VecX y;                   // y_i^gamma: n x s
  std::vector<Mat6> D1F, D2F;  // D_1F̄_i^a, D_2F̄_i^a of the discrete impulse, a = 0..s-1
  // Scratch of one body
  std::vector<Vec6> Theta, Xi;  // Θ̄^{a rho} (s x (s+1)), Ξ̄^{a nu} (s x s), as column vectors
  VecX xi;                      // ξ̄^a
  MatX Lambda;                  // Λ_i, s x s
  // Forward pass
  std::vector<Twist> eta, dv;   // η̄_i^nu (n x s), spatial variation δ̄v̄_i^rho (n x (s+1))
};

// Computes dq (n x s, column gamma-1 = δq^{k,gamma}) from the state left in `del` by the last
// del_residual call and its residual r (n x s). Returns false if a pivot block Λ_i is singular
// (ERRATA A-8), leaving dq unspecified.
bool newton_direction(const Model& model, const Quadrature& quad, DelWorkspace& del, NewtonWorkspace& ws,
                      const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> dq);

}  // namespace hovi
