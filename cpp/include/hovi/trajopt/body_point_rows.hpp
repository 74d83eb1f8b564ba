// The path constraints on body points (python/hovi/trajopt/path_constraints.py, OnBodyPoints) that
// share a set of configurations, each a weighted sum of the transcription's configuration points,
// q_p = sum_k w[p, k] q(point k) (a point itself, or a configuration between two on the polynomial):
//   row (p, i) = c_i + sum_m L[i, m] . x_b + D[i, m] . (x_b * x_b),  b = idx[i, m],
// x_b the world position of body point b at q_p. Its Hessian is exact: with the world vector
// F_b = sum_i lambda_(p,i) (L + 2 D x_b) of each point, d(J_b^T F_b)/dq (body_points.hpp), plus
// 2 sum lambda J_b^T diag(D) J_b for the squares.
#pragma once
#include <vector>

#include "hovi/algorithms/body_points.hpp"
#include "hovi/trajopt/row_block.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

using IndexMatrix = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

class BodyPointRows : public RowBlock {
 public:
  // offsets (P x K): where q(point k) of configuration p starts in x; weights (P x K); bodies (B),
  // local (B x 3): the points in the bodies' joint frames; c (R), L and D (R M x 3; row i M + m), idx (R x M): the rows' form.
  // InputError naming the argument unless consistent and finite.
  BodyPointRows(const Model& model, int n_variables, IndexMatrix offsets, MatX weights, std::vector<int> bodies,
                MatX local, VecX c, MatX L, MatX D, IndexMatrix idx);

  int n_variables() const override { return nv_; }
  int rows() const override { return P_ * R_; }                  // (p, i)
  int nnz() const override { return P_ * R_ * K_ * n_; }         // (p, i, k, j), every joint j
  void values(const VecX& x, Eigen::Ref<VecX> g) const override;
  void jacobian(const VecX& x, Eigen::Ref<VecX> values) const override;
  const SparsityStructure& hessian_structure() const override { return hs_; }
  void hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const override;

 private:
  // The configurations q_p at x, n x P.
  MatX configurations(const VecX& x) const;
  // The position of row i's m-th point at configuration p, a column of X (3 x (B P), body_points.hpp).
  Vec3 point(int i, int m, int p, const MatX& X) const { return X.col(p * B_ + idx_(i, m)); }
  // (L + 2 D x_b) of row i's m-th point at x_b.
  Vec3 slope(int i, int m, const Vec3& xb) const;

  Model model_;
  int nv_, n_, P_, K_, B_, R_, M_;
  IndexMatrix offsets_, idx_;
  MatX weights_, local_, L_, D_;   // local_: the points in the bodies' COM frames, 3 x B
  VecX c_;
  std::vector<int> bodies_;
  std::vector<int> joints_;      // the joints on the points' paths to the root, ascending
  bool squares_;                 // some D != 0
  SparsityStructure hs_;         // per p: (k, l, a, b) over the joints a, b, lower triangle in x
  mutable WorkspacePool<BodyPointWorkspace> pool_;
};

}  // namespace hovi
