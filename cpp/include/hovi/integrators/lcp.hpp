// The linear complementarity problem of one Newton iteration of the contact step: find z >= 0 with
// w = M z + b >= 0 and z_i w_i = 0. Tried first on a guessed basis (the previous iteration's or
// step's active set: one dense solve, and in a steady contact the only one), then by Lemke's
// complementary pivoting (Cottle, Pang and Stone, The Linear Complementarity Problem, 4.4), which
// solves the Stewart-Trinkle LCP of a time step (Stewart and Trinkle 1996). The basis found is
// re-solved densely, so the nonbasic z and the basic w are exactly zero. Where Lemke ends on a ray of
// a feasible problem (redundant contacts), it is run again on M + eps I with a tiny eps (lcp.cpp).
#pragma once
#include <vector>

#include "hovi/spatial/types.hpp"

namespace hovi {

class LcpSolver {
 public:
  // basis: on entry a guess (basis[i] != 0: z_i basic, w_i = 0), on exit the solution's; z gets the
  // solution. False if Lemke ends on a secondary ray or exceeds its pivots (no solution found).
  bool solve(const MatX& M, const VecX& b, VecX& z, std::vector<char>& basis);
  int pivots() const { return pivots_; }  // of the last solve (0: the guess or z = 0 held)

 private:
  // z from the basis by a dense solve; true if z >= 0 and w >= 0 to the relative round-off tol.
  bool solve_basis(const MatX& M, const VecX& b, const std::vector<char>& basis, VecX& z, double tol);
  bool lemke(const MatX& M, const VecX& b, std::vector<char>& basis);
  MatX T_, Mbb_, Mreg_;
  VecX rhs_, w_;
  std::vector<int> rows_, var_;
  int pivots_ = 0;
};

}  // namespace hovi
