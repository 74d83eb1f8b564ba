// Lobatto quadrature on [0, 1] with s+1 points (paper Sec. 2.1): exact for polynomials of
// degree 2s-1; the Galerkin integrator built on it has order 2s. s = 1 is the trapezoidal
// rule, s = 2 Simpson's.
#pragma once
#include "hovi/spatial/types.hpp"

namespace hovi {

struct Quadrature {
  explicit Quadrature(int s);  // throws InputError unless 1 <= s <= 16

  int s;    // number of intervals; s+1 control points
  VecX c;   // nodes c^0 = 0 < c^1 < ... < c^s = 1 (control point times t^{k,a} = (k + c^a) dt)
  VecX w;   // weights w^a, sum 1
  MatX b;   // differentiation matrix b^{ab} = l_b'(c^a), so q̇^a = (1/dt) sum_b b^{ab} q^b (docs/paper.md C-1)
  MatX a;   // a^{ab} = w^b b^{ba} (Prop. 1, docs/paper.md C-2)

  // Lagrange basis l_b(x) at x (x may lie outside [0, 1], for extrapolation).
  VecX basis(double x) const;
  // Its derivative l_b'(x) (at the nodes, row a of b).
  VecX basis_derivative(double x) const;
};

}  // namespace hovi
