// One step of the Galerkin variational integrator with hard point contacts and Coulomb friction:
// the DEL equations with the contact impulses, and the complementarity conditions of the
// trajectory optimiser (python/hovi/contact/contacts.py; Stewart and Trinkle 1996 in Manchester
// and Kuindersma's variational form). Per contact c, with impulses applied at the step's start
// configuration q^k and paired with the motion to its end point q^{k+1} = q^{k,s}:
//   r^{k,0} + J_c(q^k)^T (λ_c e_z + D^T β_c) = 0,   r^{k,1..s-1} = 0         (DEL with impulses)
//   0 <= λ_c       ⊥  φ_c(q^{k+1}) >= 0                                         (no penetration, no pull)
//   0 <= γ_c       ⊥  μ λ_c - Σ_i β_c,i >= 0                                   (friction cone)
//   0 <= β_c,i     ⊥  γ_c + D_i . (x_c(q^{k+1}) - x_c(q^k)) >= 0               (maximal dissipation)
// λ and β are impulses (N s: the trajectory optimiser's knot forces times (w^0 + w^s) dt), γ the
// sliding displacement over the step (m). The solve is Newton's method on this nonsmooth system
// (Josephy-Newton): each iteration linearises the DEL equations (the exact recursive direction,
// O(s^3 n), and 3C solves for the contact impulses' columns) and the gaps, and solves the resulting
// LCP in the impulses exactly (lcp.hpp); the one Newton driver (newton_driver.hpp) runs it, with
// a line search on ||(r, min(z, w))||_2. Converged when the DEL correction is at round-off and
// every |min(z_i, w_i)| <= tol: no penetration and complementarity to that tol (m and N s).
#pragma once
#include <memory>
#include <vector>

#include "hovi/algorithms/del_residual.hpp"
#include "hovi/algorithms/newton_direction.hpp"
#include "hovi/model/contact_model.hpp"
#include "hovi/integrators/lcp.hpp"
#include "hovi/integrators/dense_direction.hpp"
#include "hovi/integrators/newton_solver.hpp"

namespace hovi {

class ContactSolver {
 public:
  // model and contacts must outlive the solver (checked by the caller: ContactModel::check).
  ContactSolver(const Model& model, const Quadrature& quad, const ContactModel& contacts);

  // qc (n x (s+1)): column 0 = q^k, columns 1..s the guess / solution; z (unknowns()): the guess /
  // solution (per contact λ, β_1..d, γ); basis: the LCP's active set, guess / solution; u: m x (s+1).
  SolveInfo solve(const SolverOptions& opt, double tol, const Eigen::Ref<const VecX>& p,
                  const Eigen::Ref<const MatX>& u, double dt, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> z,
                  std::vector<char>& basis, Eigen::Ref<VecX> p_next);

  // The free base's chart about its centre (Model::chart_placement) in the solver's kinematics.
  void set_chart_placement(const SE3& placement) { data_.chart_placement = del_.chart_placement = placement; }

  // At the iterate of the last solve: φ_c(q^{k+1}) (C) and the complements w (unknowns()).
  const VecX& gaps() const { return cur_.phi; }
  const VecX& complements() const { return cur_.w; }
  int lcp_pivots() const { return pivots_; }  // LCP pivots over the last solve
  // J(q^k)^T (λ_c e_z + D^T β_c) summed over the contacts: the generalized impulse of z at the q^k of
  // the last solve.
  VecX knot_impulse(const Eigen::Ref<const VecX>& z) const;

  // The step's equations at (qc, z) without solving: r (n x s, with the impulses), the gaps and
  // complements, p^{k+1}.
  void evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& z, MatX& r, VecX& phi, VecX& w,
                Eigen::Ref<VecX> p_next);

 private:
  struct State {
    MatX R, R0;    // n x s: the residual with and without the impulses
    VecX p_next;   // p^{k+1}
    MatX Xe, Je;   // 3 x C and 3C x n: contact points and their Jacobians at q^{k+1}
    VecX h, phi;   // C: the height each point keeps (the terrain's below it plus its radius), the gaps
    VecX w, nu;    // unknowns(): the complements and the natural residual min(z, w)
  };
  struct Step;  // the Problem of newton_iterate (contact_solver.cpp)
  void start(const Eigen::Ref<const VecX>& q0);  // X0_, J0_ at q^k
  void evaluate(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, double dt,
                const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& z, State& st);
  // After factor(): W3_, K_ and the LCP's matrix M_ of the linearisation (false if not finite).
  bool linearize();
  // With them, the LCP's right-hand side at the current iterate and its solution: z_new_, dy_, dz_;
  // false if it has none.
  bool solve_linearization(const Eigen::Ref<const VecX>& z, std::vector<char>& basis);
  // Factors the DEL Jacobian at the current iterate on the path the options choose (the dense LU
  // below the crossover in n, as the integrator's direction: each of the 3C + 1 solves of an
  // iteration then costs O(s^2 n^2) instead of the recursion's large O(s^2 n)); false if singular.
  bool factor(const SolverOptions& opt, const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& u, double dt);
  void solve_rhs(const Eigen::Ref<const MatX>& r, Eigen::Ref<MatX> out);  // out = -J^{-1} r

  const Model& model_;
  const Quadrature& quad_;
  const ContactModel& contacts_;
  int n_, s_, C_, d_, nz_;
  MatX r_com_;        // 3 x C: the points in their body's COM frame
  Data data_;         // forward kinematics at q^k
  DelWorkspace del_;
  NewtonWorkspace newton_;
  std::unique_ptr<DenseDirection> dense_;  // made on first use of the dense path
  bool dense_path_ = false;
  LcpSolver lcp_;
  MatX X0_, J0_;      // 3 x C, 3C x n at q^k
  State cur_, trial_;
  MatX d0_, W3_, K_, M_, rhs_, dy_, q_trial_;
  VecX a_, b_, z_new_, dz_, z_trial_, F_;
  int pivots_ = 0;
};

}  // namespace hovi
