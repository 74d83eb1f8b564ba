// Discrete Riccati equations of LQR on a step map x^{k+1} = A x^k + B u^k with the stage cost
// x^T Q x + u^T R u (no factor 1/2) and cost-to-go x^T P x; the policy u = -K x.
#pragma once
#include <vector>

#include "hovi/spatial/types.hpp"

namespace hovi {

// The stabilising solution P of P = Q + A^T P A - A^T P B (R + B^T P B)^{-1} B^T P A and its gain
// K = (R + B^T P B)^{-1} B^T P A, by the structure-preserving doubling algorithm (quadratic
// convergence; no eigenvectors). Throws InputError for mismatched sizes, non-finite entries, R not
// positive definite, or no convergence in 100 doublings ((A, B) not stabilisable or (A, Q) not
// detectable). iterations: the doublings taken.
void discrete_are(const MatX& A, const MatX& B, const MatX& Q, const MatX& R, MatX& P, MatX& K,
                  int* iterations = nullptr);

// Finite horizon: P^N = QN and for k = N-1..0, K^k = (R^k + B^T P^{k+1} B)^{-1} B^T P^{k+1} A and
// P^k = Q^k + K^T R K + (A - B K)^T P^{k+1} (A - B K) (Joseph form, symmetric to round-off).
// Q and R hold one matrix per stage, or one for all. Ps gets N+1 matrices, Ks N.
void backward_riccati(const std::vector<MatX>& A, const std::vector<MatX>& B, const std::vector<MatX>& Q,
                      const std::vector<MatX>& R, const MatX& QN, std::vector<MatX>& K, std::vector<MatX>& P);

}  // namespace hovi
