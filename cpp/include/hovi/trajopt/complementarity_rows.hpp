// The contact complementarity rows of a trajectory-optimisation problem (python/hovi/trajopt/
// complementarity.py states them, their pairing, bounds and Jacobian structure) evaluated in C++
// with their exact Hessian. Per pair e = 0..P-2 of configuration points and contact c (inputs
// lambda, beta_1..d, gamma at point e; x_c(q) the contact point's world position):
//   phi = z - h(x, y) at q_{e+1};  psi = mu lambda - sum beta;  zeta_k = gamma + D_k . (x(q_{e+1}) - x(q_e)) / dt_e;
//   lambda phi;  gamma psi;  beta_k zeta_k;  and the last point's inputs held equal to the one before.
// h is piecewise constant, so the rows' second derivatives in q are those of x: one world vector per
// contact and point through d(J^T F)/dq (body_points.hpp); the products add their cross terms.
#pragma once
#include <vector>

#include "hovi/model/contact_model.hpp"
#include "hovi/algorithms/body_points.hpp"
#include "hovi/trajopt/row_block.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

class ComplementarityRows : public RowBlock {
 public:
  // contacts: the points, the terrain (its height), mu and the friction directions;
  // first_input: the control index of contact 0's normal input (each contact's inputs lambda,
  // beta_1..d, gamma follow, ContactModel::per_contact()); t (P): the configuration points' times,
  // increasing; q_off, u_off (P): where their configuration and controls start in x.
  ComplementarityRows(const Model& model, int n_variables, ContactModel contacts, int first_input, VecX t,
                      Eigen::VectorXi q_off, Eigen::VectorXi u_off);

  int n_variables() const override { return nv_; }
  int rows() const override { return E_ * C_ * (4 + 2 * d_) + hold_; }
  int nnz() const override;
  void values(const VecX& x, Eigen::Ref<VecX> g) const override;
  void jacobian(const VecX& x, Eigen::Ref<VecX> values) const override;
  const SparsityStructure& hessian_structure() const override { return hs_; }
  void hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const override;

 private:
  // The contact points' positions (and Jacobians) at every point into w: X 3 x (C P), J 3 x (n C P), column p C + c.
  void points(const VecX& x, BodyPointWorkspace& w, bool jacobians) const;
  // x's offset of contact c's input at point e: what 0 lambda, 1 + k beta_k, 1 + d gamma.
  int input(int e, int c, int what) const { return u_off_[e] + first_ + c * (2 + d_) + what; }
  auto jac(const BodyPointWorkspace& w, int p, int c) const { return w.J.middleCols((p * C_ + c) * n_, n_); }

  Model model_;
  ContactModel ct_;
  int nv_, n_, P_, E_, C_, d_, first_, hold_;
  VecX dt_;
  Eigen::VectorXi q_off_, u_off_;
  std::vector<int> bodies_;              // the contact points' bodies
  MatX r_com_;                           // the contact points in their bodies' COM frames, 3 x C
  std::vector<std::vector<int>> path_;   // joints on each contact body's path to the root
  std::vector<int> joints_;              // their union, ascending
  SparsityStructure hs_;
  mutable WorkspacePool<BodyPointWorkspace> pool_;
};

}  // namespace hovi
