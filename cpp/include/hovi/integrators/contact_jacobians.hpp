// The linearisation of one converged contact step (contact_solver.hpp), the contact part of
// Linearizer (linearizer.hpp), by the implicit function
// theorem with its contact state held: the step map (q^k, p^k, u^k) -> (q^{k+1}, p^{k+1}) with
// p^{k+1} the state the next step starts from. Per contact with a normal impulse λ_c > 0:
//   stick (γ_c = 0, to 1e-12 m): φ_c(q^{k+1}) = 0 and T (x_c(q^{k+1}) - x_c(q^k)) = 0 (T: the tangent axes the
//     friction directions span), the impulse λ_c e_z + T^T f_c with λ_c, f_c unknowns;
//   slide (γ_c > 0): φ_c(q^{k+1}) = 0, the impulse λ_c (e_z + μ t_c) along the friction
//     direction t_c = D^T β_c / Σ β_c of the solution, λ_c unknown;
// a contact without normal impulse adds nothing. With y = q^{k,1..s} and those impulses as the
// unknowns of R = 0 (the DEL equations with J_c(q^k)^T F_c in r^{k,0}, whose q^k-derivative is
// body_point_force_derivative), dy/dx = -(dR/dy)^{-1} dR/dx, as linearizer.hpp. Exact away from
// contact switches (a contact landing, lifting off, starting or stopping to slide within the
// perturbation), where the step map is not differentiable.
#pragma once
#include <functional>

#include "hovi/algorithms/del_jacobian.hpp"
#include "hovi/integrators/free_base_jacobians.hpp"
#include "hovi/model/contact_model.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

class ContactJacobians {
 public:
  // model, quad, contacts and free (a free base's Jacobians, or null) must outlive it.
  ContactJacobians(const Model& model, const Quadrature& quad, double dt, const ContactModel& contacts,
                   const FreeBaseJacobians* free = nullptr);

  // A (2n x 2n) and/or B (2n x (s+1) m) at converged control points qc (n x (s+1)) with controls u
  // (m x (s+1)) and impulses z (unknowns(), the step's solution). Redundant contacts held: the
  // least-norm impulses and the one motion. False if the rows are inconsistent or dR/dy singular
  // in the motion.
  bool step_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                      const Eigen::Ref<const VecX>& z, MatX* A, MatX* B, const Mat3* centre = nullptr) const;
  // Smoothed across contact switches (smoothing > 0, in (N s)^2): every complementarity pair (z_i, w_i)
  // of the step, in impulse units (a gap or displacement over its impulse's own mobility through the
  // step), linearised on the central path z~_i w~_i = smoothing through the solution (both moved by the
  // same δ >= 0: z~ = z + δ, w~ = w + δ), w~_i dz_i + z~_i dw_i = 0, as the gradients of an
  // interior-point step (Dojo's). A pair far from its switch (z_i w~_i >> smoothing) keeps its side as
  // in step_jacobians, to O(smoothing); a pair at it (z = w = 0: a contact touching without load, a
  // sticking contact at its friction limit) blends both sides. All of z's unknowns enter.
  // A free base: centre is the chart's (q^k's attitude), A and B in tangent coordinates
  // (free_base_jacobians.hpp); a turn of the centre moves the contact points as the chart coordinates
  // θ^a + A(θ^a) E(0)^-1 δω would.
  bool smoothed_jacobians(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                          const Eigen::Ref<const VecX>& z, double smoothing, MatX* A, MatX* B,
                          const Mat3* centre = nullptr) const;

 private:
  struct Workspace {
    Workspace(const Model& model, const Quadrature& quad) : ws(model, quad), data(model), res(model, quad) {}
    DelJacobianWorkspace ws;
    Data data;
    DelWorkspace res;  // a free base's residual
    MatX Jq, Ju, K, rhs, sol, J0, Je, H, X0, Xe, r;
    VecX pn;
  };
  // The step's DEL Jacobian (Jq, and Ju if want_u) and the contact points at q^k and q^{k+1} (X0, Xe,
  // their Jacobians J0, Je) with d(Σ J_c(q^k)^T F_c)/dq^k (H) for the impulses z, into w. A free base:
  // all in the chart about centre, Jq with its centre term's derivative, r and pn the residual at p^k = 0.
  void point_kinematics(Workspace& w, const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u,
                        const Eigen::Ref<const VecX>& z, bool want_u, const Mat3* centre) const;
  // A and B from the implicit function theorem: solve(b, x) gives x = -(dR/dy)^{-1} b (false: failed)
  // for the ny unknowns; A's right-hand side d/d(q^k, p^k) is w.rhs (ny x 2n), B's is built here. A free
  // base (centre): A and B in tangent coordinates.
  bool step_maps(Workspace& w, int ny, const std::function<bool(const MatX&, MatX&)>& solve, MatX* A, MatX* B,
                 const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, const Eigen::Ref<const VecX>& z,
                 const Mat3* centre) const;
  // step_maps of a free base: w.rhs's first n columns (by q^{k,0} in the chart) and rhs_u (by u) mapped to the
  // tangent inputs and outputs.
  bool tangent_maps(Workspace& w, int ny, const std::function<bool(const MatX&, MatX&)>& solve, MatX* A, MatX* B,
                    const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, const Eigen::Ref<const VecX>& z,
                    const Mat3& centre, const MatX& rhs_u) const;
  const Model& model_;
  const Quadrature& quad_;
  double dt_;
  const ContactModel& contacts_;
  const FreeBaseJacobians* free_;
  MatX r_com_, T_;  // 3 x C points in their COM frames; the tangent axes (rows) the directions span
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
