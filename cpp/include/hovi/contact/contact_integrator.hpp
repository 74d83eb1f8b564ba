// The Galerkin variational integrator with hard point contacts (contact_solver.hpp): steps and
// rollouts in C++. A step whose contacts were all inactive in the step before is first solved
// without contact (the integrator's own step, nothing of the contacts computed but the gaps at
// its end); if no contact point ends below the terrain, that is the step (zero impulses solve
// its complementarity conditions). Otherwise, and whenever a contact was active, the contact
// step is solved, warm-started from the previous step's impulses and LCP active set.
//
// Impact location (locate_impacts): when that free step ends below the terrain, the impact time
// t^k + θ dt is found on the step's polynomial (the first root of the smallest gap along it, then
// refined by Newton on θ for the gap at the end of the free piece), and the step is split there: a free step of θ dt to the impact, then a contact step of (1 - θ) dt
// whose impulses act at the impact configuration. The free flight keeps the order 2s of the
// integrator and impacts happen at their time (to that order) instead of at the next knot; the
// step's recorded control points are the two pieces' polynomial at the step's nodes. Without it
// (s = 1 by default) the step is the trajectory optimiser's time-stepping, which it reproduces.
#pragma once
#include <vector>

#include "hovi/contact/contact_solver.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"

namespace hovi {

// The momenta of a contact rollout: p^k for 0 < k < K includes half the impulse at q^k (the share
// w^s/(w^0 + w^s) of the trajectory optimiser's knot momentum: a body at rest has p = 0); p^0 is the
// given state (and likewise includes half its knot's impulse when the rollout continues another,
// z0 given) and p^K the state the next step starts from, before its knot's impulse.
struct ContactRollout : Rollout {
  MatX impulses;           // N x unknowns(): row k = per contact (λ, β_1..d, γ) of step k
  MatX gaps;               // N x C: φ_c(q^{k+1})
  Eigen::VectorXi pivots;  // LCP pivots of step k (0: solved without contact, or on the guessed active set)
  VecX impact;             // N: θ of a step split at an impact at t^k + θ dt (its impulses act there), else 0
  MatX step_p;             // (N+1) x n: the momentum each step starts from, before its knot's impulse (the state
                           // of the step's Jacobians and of a feedback policy; p without the half impulse)
};

class ContactIntegrator {
 public:
  // Throws ModelError / InputError for contacts that do not fit the model (ContactModel::check), a
  // model with holonomic constraints (not supported with contacts) or bad options; tol: the
  // complementarity tolerance, |min(z_i, w_i)| <= tol (m and N s), in (0, 1e-3].
  ContactIntegrator(Model model, ContactModel contacts, int s, double dt, SolverOptions options = {},
                    double tol = 1e-10, bool locate_impacts = false);
  ContactIntegrator(const ContactIntegrator&) = delete;
  ContactIntegrator& operator=(const ContactIntegrator&) = delete;

  const GalerkinIntegrator& integrator() const { return free_; }
  const ContactModel& contacts() const { return contacts_; }
  double tol() const { return tol_; }
  bool locate_impacts() const { return locate_; }

  // One step from q^k = qc.col(0) with momentum p and controls u (m x (s+1)); z: the first guess of
  // the impulses (zeros: none active) and, on exit, the solution; phi gets φ_c(q^{k+1}); qc the
  // control points; pivots (if given) the LCP pivots. previous: the control points of the step
  // before (or empty).
  // pivots (if given) the LCP pivots; impact (if given) the θ of a split step, else 0.
  SolveInfo step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, const Eigen::Ref<const MatX>& previous,
                 Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi,
                 int* pivots = nullptr, double* impact = nullptr) const;

  // N steps from (q0, p0); u: N x ((s+1) m) as GalerkinIntegrator::rollout; z0: the impulses of the step
  // before (empty: none active). Stops at the first failed step.
  // hook: as GalerkinIntegrator::rollout's (the state it sees is (q^k, p^k) before the knot's impulse).
  ContactRollout rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, const VecX& z0 = VecX(),
                         StepHook* hook = nullptr) const;

 private:
  struct Workspace {
    Workspace(const Model& model, const Quadrature& quad, const ContactModel& contacts)
        : solver(model, quad, contacts), newton(model, quad), data(model) {}
    ContactSolver solver;
    NewtonSolver newton;  // the free piece of a step split at an impact
    Data data;
    std::vector<char> basis;
  };
  SolveInfo step(Workspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                 const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                 Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi,
                 int& pivots, double& impact) const;
  // The smallest gap of the contact points at configuration q.
  double smallest_gap(Workspace& ws, const Eigen::Ref<const VecX>& q) const;
  // The first root θ in (0, 1] of the smallest gap along the polynomial of the control points qc
  // (whose end is below the terrain), or 0 if it starts there.
  double impact_time(Workspace& ws, const Eigen::Ref<const MatX>& qc) const;
  // The step split at θ (impact_time, refined on the free piece's end: θ on exit): a free step of
  // θ dt, then a contact step; qc holds the free step's control points on entry and the pieces'
  // polynomial at the nodes on exit.
  SolveInfo split_step(Workspace& ws, double& theta, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                       Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi,
                       int& pivots) const;
  // Without contact: the gaps at q^{k+1} = qc.col(s); true (and z = the inactive solution) if none is negative.
  bool free_step_holds(Workspace& ws, const Eigen::Ref<const MatX>& qc, Eigen::Ref<VecX> z, Eigen::Ref<VecX> phi) const;

  GalerkinIntegrator free_;
  ContactModel contacts_;
  double tol_;
  bool locate_;
  MatX r_com_;  // 3 x C: the points in their body's COM frame
  mutable WorkspacePool<Workspace> pool_;
};

}  // namespace hovi
