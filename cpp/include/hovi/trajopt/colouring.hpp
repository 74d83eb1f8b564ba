// Colourings of a symmetric sparsity pattern for differencing a Hessian (python/hovi/trajopt/hessian.py
// documents the method): variables of one colour are perturbed together.
#pragma once
#include <Eigen/Core>
#include <utility>

namespace hovi {

// A pattern in compressed rows (indptr (rows + 1,), indices); a symmetric one for the colourings,
// the diagonal optional.
struct Pattern {
  Eigen::Ref<const Eigen::VectorXi> indptr, indices;
  int size() const { return static_cast<int>(indptr.size()) - 1; }
};

// The symmetric pattern of A^T A + I for a pattern A (rows x nv, compressed rows): variables that
// share a row of A are coupled. Returns (indptr, indices), sorted.
std::pair<Eigen::VectorXi, Eigen::VectorXi> gram_pattern(const Pattern& A, int nv);

// Greedy colours: no two variables within distance two (coupled, or with a common neighbour) share
// one (Curtis, Powell and Reid), in the order 0 .. nv - 1.
Eigen::VectorXi distance2_colouring(const Pattern& P);

// Greedy star colours, densest rows first (Gebremedhin, Manne and Pothen, SIAM Review 2005,
// Algorithm 4.1): coupled variables differ, and every path v-w-x-y uses at least three colours, so
// each entry H_ij can be read from one side alone. The diagonal is ignored.
Eigen::VectorXi star_colouring(const Pattern& P);

}  // namespace hovi
