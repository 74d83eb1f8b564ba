// Hermite-Simpson direct collocation as the dynamics of a trajectory optimisation, in the
// implicit or explicit form of the paper's Table 1 (and its footnote), for comparison with the
// VI transcription. Points i = 0..2N: even i the knot i/2 (t = (i/2) h), odd i the midpoint of
// interval (i-1)/2; h = dt.
//
// Variables x: q_i and v_i at every point, a_i at every point (implicit form only), controls
// (per point u_i, or held u_k per interval: point i uses interval min(i/2, N-1)'s, so a shared
// knot uses the control of the interval it starts), multipliers λ_i at every point (constrained).
// Constraints g(x) = 0, in this order:
//   per interval k (knots 0 = 2k, 1 = 2k+2, midpoint m = 2k+1), 4n rows:
//     q_m - (q_0 + q_1)/2 - h/8 (v_0 - v_1),   v_m - (v_0 + v_1)/2 - h/8 (a_0 - a_1),
//     q_1 - q_0 - h/6 (v_0 + 4 v_m + v_1),     v_1 - v_0 - h/6 (a_0 + 4 a_m + a_1);
//   implicit: the dynamics ID(q_i, v_i, a_i) - Q(q_i, v_i, u_i, λ_i) = 0 at every point (n rows),
//     with Q the joint forces, body wrenches and constraint forces Dh^T λ (force_jacobians.hpp);
//     explicit: a_i = M^{-1} (Q - ID(q_i, v_i, 0)) inside the collocation rows;
//   constrained: ḧ(q_i, v_i, a_i) = Dh a + (d/dt Dh) v = 0 at every point, and h(q_0) = 0,
//     Dh(q_0) v_0 = 0 once (index reduction: with h and ḣ at every point as well, as the paper
//     counts, each interval would carry 4 m_c more equations than unknowns).
// Jacobian: exact (RNEA derivatives, force Jacobians, constraint Hessians from the constraint
// force elements) except the q-derivative of (d/dt Dh) v, a third derivative of h, taken by
// central differences of the exact v^T ∇²h(q) v.
#pragma once
#include "hovi/algorithms/force_jacobians.hpp"
#include "hovi/algorithms/rnea_derivatives.hpp"
#include "hovi/model/data.hpp"
#include "hovi/trajopt/transcription.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

class HermiteSimpsonTranscription : public Transcription {
 public:
  // Throws InputError unless N >= 1 and dt > 0 finite; ModelError for an empty model.
  HermiteSimpsonTranscription(const Model& model, int N, double dt, ControlMode controls, bool implicit);

  int n_variables() const override { return n_variables_; }
  int n_constraints() const override { return n_rows_; }
  const SparsityStructure& structure() const override { return structure_; }
  void constraints(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> g) const override;
  void jacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<VecX> values) const override;

  bool implicit() const { return implicit_; }
  int N() const { return N_; }
  int n_points() const { return 2 * N_ + 1; }
  int n_control_values() const { return controls_ == ControlMode::PerPoint ? n_points() : N_; }
  // Offsets into x: q_i at q_offset() + i n, v_i at v_offset() + i n, a_i at a_offset() + i n
  // (implicit; -1 otherwise), controls at u_offset() + j m, λ_i at lambda_offset() + i m_c.
  int q_offset() const { return 0; }
  int v_offset() const { return n_points() * n_; }
  int a_offset() const { return implicit_ ? 2 * n_points() * n_ : -1; }
  int u_offset() const { return (implicit_ ? 3 : 2) * n_points() * n_; }
  int lambda_offset() const { return u_offset() + n_control_values() * m_; }

 private:
  // What the rows need at one point: a (explicit: computed) and the dynamics' derivatives.
  struct Point {
    VecX a, tau;       // acceleration (explicit: computed); ID - Q (implicit)
    MatX dq, dv, dw;   // implicit: d(ID - Q)/d(q, v, w); explicit: da/d(q, v, w); w = [u; λ]
    MatX M;            // implicit: d(ID - Q)/da = M(q)
  };
  struct Workspace {
    Workspace(const Model& model, const Model& aug, const Model& geometry);
    Data data;
    ForceJacobians forces, hessian;
    RneaDerivatives rnea;
    VecX w, h;
    MatX Dh;
  };
  int u_index(int i) const;
  void inputs(const Eigen::Ref<const VecX>& x, int i, Workspace& ws, VecX& q, VecX& v, VecX& a) const;
  void evaluate_point(const Eigen::Ref<const VecX>& x, int i, bool derivatives, Workspace& ws, Point& pt) const;
  // ḧ = Dh a + (d/dt Dh) v and, if J, its Jacobian blocks in q (mc x n), v (mc x n).
  void constraint_acceleration(const VecX& q, const VecX& v, const VecX& a, Workspace& ws, VecX& value, MatX* Jq,
                               MatX* Jv) const;
  // Hv.row(c) = (∇²h_c(q) v)^T, the constraint Hessians from the constraint force elements.
  void hessian_times(const VecX& q, const VecX& v, Workspace& ws, MatX& Hv) const;
  void build_structure();

  Model model_, aug_, geometry_;  // the model; with constraint forces ([u; λ]); constraint forces only
  int N_, n_, m_, mc_;
  double dt_;
  ControlMode controls_;
  bool implicit_;
  int n_variables_, n_rows_, dyn_row_, con_row_;
  SparsityStructure structure_;
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
