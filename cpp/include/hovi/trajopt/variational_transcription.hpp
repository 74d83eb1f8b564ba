// The Galerkin variational integrator of order 2s as the dynamics of a trajectory optimisation
// (the paper's Sec. 6 and Table 1): N stages of length dt, each the DEL equations of one step.
//
// Variables x (offsets below):
//   q^j   configurations at the N s + 1 control-point times t^{k s + a} = (k + c^a) dt (Lobatto
//         nodes); q^{k,a} = q^{k s + a}, so neighbouring stages share q^{k,s} = q^{k+1,0}
//   p^k   discrete momenta at the N + 1 knots (variables: every stage's rows then touch only its
//         own control points and the two momenta at its ends)
//   u     controls: per point u^j (N s + 1 of them; u^{k,a} = u^{k s + a}), or held u^k (N)
//   λ     multipliers λ^{k,a} (a = 0..s-1) of a constrained model, N s m_c (λ^{k,s} = 0: the
//         constraint impulse at a knot belongs to the next stage's λ^{k+1,0})
// Constraints g(x) = 0, stage k (rows (s+1) n):
//   r^{k,a}(q^{k,0..s}, u^{k,·}, λ^{k,·}) (with p^k in r^{k,0}),  a = 0..s-1   (Algorithm 1)
//   p^{k+1} - D_{s+1} L_d - F_d^{k,s}                                         (momentum update)
// then the holonomic constraints h(q^j) = 0 at every control point j = 0..N s (m_c each).
// Jacobian blocks from the linearisation (del_jacobian.hpp): per stage a dense (s+1) n square
// block in q^{k,0..s}, identities in p^k, p^{k+1}, n x m blocks in the controls and n x m_c in
// the multipliers of each control point, and the m_c x n blocks of Dh(q^j).
#pragma once
#include <memory>

#include <vector>

#include "hovi/algorithms/del_hessian.hpp"
#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/algorithms/del_workspace.hpp"
#include "hovi/model/data.hpp"
#include "hovi/trajopt/transcription.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

class VariationalTranscription : public Transcription {
 public:
  // Throws InputError unless N >= 1, dt > 0 finite, 1 <= s <= 16; ModelError for an empty model.
  VariationalTranscription(const Model& model, int s, int N, double dt, ControlMode controls);

  int n_variables() const override { return n_variables_; }
  int n_constraints() const override { return n_rows_; }
  const SparsityStructure& structure() const override { return structure_; }
  void constraints(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> g) const override;
  void jacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> values) const override;
  // Per stage, the lower triangle of the dense Hessian over its variables (control points, the
  // inputs they use, multipliers) from del_hessian.hpp; then, with holonomic constraints, per
  // control point j that of lambda_h . h(q^j) by central differences of Dh^T lambda_h.
  bool has_hessian() const override { return true; }
  const SparsityStructure& hessian_structure() const override { return hessian_structure_; }
  void hessian(const Eigen::Ref<const VecX>& x, const Eigen::Ref<const VecX>& lambda, Eigen::Ref<VecX> values,
               int threads) const override;

  const Quadrature& quadrature() const { return quad_; }
  int N() const { return N_; }
  double dt() const { return dt_; }
  int n_points() const { return N_ * quad_.s + 1; }   // control points q^j
  int n_control_values() const { return controls_ == ControlMode::PerPoint ? n_points() : N_; }
  // Offsets into x: q^j at q_offset() + j n, p^k at p_offset() + k n, u (per point j or per stage
  // k) at u_offset() + j m, λ^{k,a} at lambda_offset() + (k s + a) m_c.
  int q_offset() const { return 0; }
  int p_offset() const { return n_points() * n_; }
  int u_offset() const { return p_offset() + (N_ + 1) * n_; }
  int lambda_offset() const { return u_offset() + n_control_values() * m_; }
  // Rows: stage k at k (s+1) n; h(q^j) at holonomic_row() + j m_c.
  int holonomic_row() const { return N_ * (quad_.s + 1) * n_; }

 private:
  struct Workspace {
    Workspace(const Model& aug, const Model& model, const Quadrature& quad);
    DelWorkspace del;
    DelJacobianWorkspace jac;
    DelHessianWorkspace hess;
    Data data;
    MatX qc, u, r, Jq, Ju, Dh, nu, Hqq, Huq, Huu, Hv;
    VecX p_next, h, g0, gp;
  };
  // The controls [u; λ] of stage k (m + m_c) x (s+1) from x.
  void stage_inputs(const Eigen::Ref<const VecX>& x, int k, Workspace& w) const;
  int u_index(int k, int a) const;  // the control value used at point a of stage k
  void build_structure();
  void build_hessian_structure();
  // The variables of stage k's Hessian (increasing) and, for each of its inputs [u; λ] at each
  // point (a (m + m_c) + r), the position among them, -1 for λ^{k,s} (not a variable).
  std::vector<int> stage_variables(int k, std::vector<int>& input_at) const;
  void holonomic_hessian(const Eigen::Ref<const VecX>& x, const Eigen::Ref<const VecX>& lambda, int j, Workspace& w,
                         Eigen::Ref<VecX> values) const;

  Model aug_;  // the model with its constraint forces ([u; λ] as controls); the model without constraints
  Model model_;
  Quadrature quad_;
  int N_, n_, m_, mc_;
  double dt_;
  ControlMode controls_;
  int n_variables_, n_rows_;
  SparsityStructure structure_, hessian_structure_;
  int stage_variables_ = 0, stage_entries_ = 0;   // per stage (the same for every stage) in the Hessian
  std::vector<int> input_at_;                     // stage_variables' input positions (the same for every stage)
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
