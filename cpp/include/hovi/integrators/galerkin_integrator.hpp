// The Galerkin variational integrator of order 2s on s+1 Lobatto control points, with the model's
// forces and constraints and, optionally, hard point contacts with Coulomb friction: one step
// (q^k, p^k, u^k) -> (q^{k+1}, p^{k+1}) made of named stages, and rollouts over many steps, in C++.
//
// A step (GalerkinIntegrator::step), in stages:
//   1 predict   first guess of q^{k,1..s}        reads the last two steps, or q^k and M^{-1} p^k  => qc guess
//   2 DEL       Newton on the DEL equations (Algorithm 1; the force elements inside r, the holonomic
//               constraints as a KKT system), with fallbacks: other guesses, continuation in h
//                                                reads q^k, p^k, u^k, qc guess        => q^{k,1..s}, p^{k+1}, λ^k
//   3 contact   (contacts) the gaps at q^{k+1}: a step whose contacts were all inactive before and
//               which ends above the terrain is done, with zero impulses
//                                                reads q^{k+1}, z^{k-1}               => φ(q^{k+1}), z^k = 0
//   4 impact    (locate_impacts) the step split at the first root θ of the smallest gap along the
//               stage-2 polynomial: a free step of θ dt, then stage 5 for (1 - θ) dt
//                                                reads stage 2's q^{k,0..s}           => θ, q^{k+θ}, p^{k+θ}
//   5 LCP       Newton with the complementarity problem in the impulses (contact_solver.hpp)
//                                                reads q^k (or q^{k+θ}), p, z guess   => q^{k,1..s}, p^{k+1}, z^k, φ
// A model without contacts runs stages 1-2 only; a step with no contact near runs stages 1-3.
//
// Controls: u^{k,a} is given at each control point (an m x (s+1) matrix per step). Samples of a
// smooth u(t) keep the order 2s; a control held constant over each step (zero-order hold) is
// integrated to order 2s for that piecewise-constant input, but is only a first-order
// approximation of a smooth u(t).
//
// Impact location: the free flight keeps the order 2s of the integrator and impacts happen at their
// time (to that order) instead of at the next knot; a split step's recorded control points are the
// two pieces' polynomial at the step's nodes. Without it (s = 1 by default) the contact step is the
// trajectory optimiser's time-stepping, which it reproduces.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "hovi/algorithms/free_base.hpp"
#include "hovi/integrators/constrained_solver.hpp"
#include "hovi/integrators/contact_solver.hpp"
#include "hovi/integrators/flow_predictor.hpp"
#include "hovi/integrators/newton_solver.hpp"
#include "hovi/integrators/step_continuation.hpp"
#include "hovi/integrators/step_hook.hpp"
#include "hovi/model/contact_model.hpp"
#include "hovi/model/data.hpp"
#include "hovi/util/workspace_pool.hpp"

namespace hovi {

// The contact stages' settings. tol: the complementarity tolerance |min(z_i, w_i)| (m and N s), in
// (0, 1e-3]; locate_impacts: stage 4.
struct ContactOptions {
  double tol = 1e-10;
  bool locate_impacts = false;
};

// The contact part of a rollout (empty without contacts). The momenta p^k of a contact rollout for
// 0 < k < K include half the impulse at q^k (the share w^s/(w^0 + w^s) of the trajectory optimiser's
// knot momentum: a body at rest has p = 0); p^0 is the given state (and likewise includes half its
// knot's impulse when the rollout continues another, z0 given) and p^K the state the next step
// starts from, before its knot's impulse.
struct RolloutContacts {
  MatX impulses;           // N x unknowns(): row k = per contact (λ, β_1..d, γ) of step k
  MatX gaps;               // N x C: φ_c(q^{k+1})
  Eigen::VectorXi pivots;  // LCP pivots of step k (0: solved without contact, or on the guessed active set)
  VecX impact;             // N: θ of a step split at an impact at t^k + θ dt (its impulses act there), else 0
  MatX step_p;             // (N+1) x n: the momentum each step starts from, before its knot's impulse (the state
                           // of the step's Jacobians and of a feedback policy; p without the half impulse)
};

// A model with a free base (Model::set_rotation_chart): q is public, (N+1) x nq, and p too (the
// base's momentum in its own frame: algorithms/free_base.hpp); step k's control points are in the
// chart about q^k's attitude (its angles 0 at q^{k,0}).
struct Rollout {
  MatX q, p;                   // (N+1) x nq and (N+1) x n: q^k, p^k
  MatX control_points;         // N x ((s+1) n): row k = vec(q^{k,0..s}) column-major (n per point)
  MatX multipliers;            // N x (s m_c): row k = vec(λ^{k,0..s-1}) column-major (constrained)
  MatX controls;               // N x ((s+1) m) as u: the controls a StepHook chose (empty without one)
  Eigen::VectorXi iterations;  // Newton iterations per step
  Eigen::VectorXi factorizations;  // of them, those with a fresh Jacobian factorisation
  VecX residual;               // final ||r||_inf per step
  std::vector<SolveStatus> status;
  int steps = 0;               // steps completed (less than N if a solve failed)
  RolloutContacts contact;     // with contacts
};

// What a step reads from the steps before it and leaves for the next (a rollout carries it; a single
// step starts from an empty one). The step's guess and solution of its multipliers and impulses.
struct StepHistory {
  // A model with a free base: the centre of the chart q^k and the points below are given in (its
  // attitude C R(θ)); the step moves it to q^k's attitude, which the step's points are then about.
  Mat3 centre = Mat3::Identity();
  MatX before_previous, previous;  // n x (s+1): the control points of the last two steps (empty: not known)
  MatX lambda;                     // m_c x s: λ^{k,0..s-1}, guess in and solution out (constrained models)
  VecX z;                          // unknowns(): the impulses, guess in (zeros: none active) and solution out
  std::vector<char> basis;         // the LCP's active set of the last contact solve
};

// What a contact step reports beyond its SolveInfo.
struct ContactReport {
  VecX phi;          // C: φ_c(q^{k+1})
  int pivots = 0;    // LCP pivots
  double impact = 0; // θ of a step split at an impact, else 0
};

// The scratch memory of one call: every public call of GalerkinIntegrator leases one from a pool,
// so that one integrator can be used from several threads at once (each call gets its own).
struct IntegratorWorkspace {
  IntegratorWorkspace(const Model& model, const Quadrature& quad, const ContactModel& contacts);
  NewtonSolver solver;
  std::unique_ptr<ConstrainedSolver> constrained;       // when the model has constraints
  std::unique_ptr<ContactSolver> contact;               // when it has contacts
  std::unique_ptr<ContinuationWorkspace> continuation;  // made at the first step_continuation
  Data data;
  FlowPredictor flow;
  VecX p_chart;  // a free base: p^k in the chart about q^k's attitude
  // The free base's chart about the centre C (its attitude at the step's start) in every workspace.
  void set_chart_centre(const Model& model, const Mat3& centre);
};

// Thread safety: the model, contacts, quadrature, dt and options are fixed at construction (do not
// change `options` while calls are running); every other call may run concurrently on one object,
// and each call's result depends on its arguments only.
class GalerkinIntegrator {
 public:
  // Throws ModelError / InputError for a model without joints, bad options, contacts that do not fit
  // the model (ContactModel::check) or contacts on a model with holonomic constraints. No contact
  // points: no contact stages.
  GalerkinIntegrator(Model model, int s, double dt, SolverOptions options = {}, ContactModel contacts = {},
                     ContactOptions contact_options = {});
  GalerkinIntegrator(const GalerkinIntegrator&) = delete;
  GalerkinIntegrator& operator=(const GalerkinIntegrator&) = delete;

  const Model& model() const { return model_; }
  const Quadrature& quadrature() const { return quad_; }
  double dt() const { return dt_; }
  SolverOptions options;
  bool has_contacts() const { return contacts_.size() > 0; }
  const ContactModel& contacts() const { return contacts_; }
  const ContactOptions& contact_options() const { return contact_options_; }

  // A free base: q public (nq), q̇ its velocity and p its momentum (algorithms/free_base.hpp).
  // p = dL/dq̇ = M(q) q̇, O(n^2). Its inverse reads a velocity back from a momentum: q̇ = M(q)^{-1} p,
  // and for a constrained model the q̇ with Dh(q) q̇ = 0 nearest to M^{-1} p in the kinetic-energy
  // metric (tangent_velocity.hpp), O(n m + m^3). The total energy K + V at (q, q̇(q, p)).
  VecX momentum(const VecX& q, const VecX& qdot) const;
  VecX velocity(const VecX& q, const VecX& p) const;
  double energy(const VecX& q, const VecX& p) const;

  // Constraints (the model's, if any): their number of equations m_c and a consistent initial
  // state: q projected onto h(q) = 0 by Gauss-Newton (minimum-norm corrections, on the Newton
  // driver), q̇ onto Dh q̇ = 0 in the kinetic-energy metric. Throws InputError for redundant or
  // inconsistent constraints, a state too far off the manifold, or constraints that lock every
  // degree of freedom.
  int n_constraints() const { return model_.n_constraints(); }
  std::pair<VecX, VecX> project(const VecX& q, const VecX& qdot, double tol = 1e-12) const;
  VecX constraint_values(const VecX& q) const;
  MatX constraint_jacobian(const VecX& q) const;

  // One step, every stage (see the top): qc (n x (s+1)) column 0 must hold q^k (a free base: in the
  // chart about history.centre; on exit the step's points and history.centre are about q^k's
  // attitude, p_next in that chart) and gets the control
  // points; history: what the steps before left (an empty one: the velocity guess, multipliers from
  // zero, no impulses active) and, on exit, this step's multipliers and impulses (kept on failure);
  // report (contacts, if given): the gaps, LCP pivots and impact. Iterations add up over the stages
  // and fallbacks.
  SolveInfo step(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc,
                 Eigen::Ref<VecX> p_next, StepHistory& history, ContactReport* report = nullptr) const;

  // Stage 2 alone, one Newton solve from a given guess (no fallbacks, no contact): qc columns 1..s
  // hold the guess on entry and the solution on exit. Constrained models: lambda (m_c x s) holds the
  // guess of λ^{k,0..s-1} on entry and the solution on exit (kept on failure); null: guess 0.
  SolveInfo solve(const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc,
                  Eigen::Ref<VecX> p_next, MatX* lambda = nullptr) const;

  // Initial guesses for columns 1..s of qc (column 0 = q^k already set): from a velocity
  // estimate, q^k + c^a dt q̇; or by extrapolating the previous step's polynomial.
  void guess_from_velocity(const VecX& qdot, Eigen::Ref<MatX> qc) const;
  void guess_from_previous(const Eigen::Ref<const MatX>& previous, Eigen::Ref<MatX> qc) const;
  // The predictor of rollouts: the least-squares polynomial of degree max(2, 2s-1) (at most 7)
  // through the 2s+1 control points of the last two steps, extrapolated to this step's points
  // and shifted through q^k; 10 to 100 times closer to the solution than extrapolating the
  // previous step alone (bench/README.md, "Design measurements").
  void guess_from_history(const Eigen::Ref<const MatX>& before_previous, const Eigen::Ref<const MatX>& previous,
                          Eigen::Ref<MatX> qc) const;

  // N steps from (q0, p0) (a free base: public q0 (nq) and p0, and the record public). u: N x ((s+1) m), row k = vec(u^{k,0..s}) column-major; may have 0
  // columns when the model has no controls. start: the history of the step before (its control
  // points for the first guess, its multipliers, its impulses; empty: none). Stops at the first
  // failed step. hook: asked for each step's controls (and impulses) instead of u (then u may be
  // empty), e.g. a feedback policy; with contacts the state it sees is (q^k, p^k) before the knot's
  // impulse.
  Rollout rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, StepHistory start = {},
                  StepHook* hook = nullptr) const;

  // The DEL residual and Newton direction at given control points (for tests and tools).
  void residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                Eigen::Ref<MatX> r, Eigen::Ref<VecX> p_next) const;
  bool direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                 Eigen::Ref<MatX> dq) const;
  // The constrained residual (r: n x s with the constraint forces, H: m_c x s) and direction
  // (ConstrainedSolver); the direction returns false if the KKT system is singular. Throws
  // InputError without constraints.
  void constrained_residual(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                            const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, MatX& r, MatX& H,
                            Eigen::Ref<VecX> p_next) const;
  bool constrained_direction(const Eigen::Ref<const MatX>& qc, const Eigen::Ref<const MatX>& lambda,
                             const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u, MatX& dz,
                             MatX& dlambda) const;

 private:
  // The stages (a model without contacts: stage 2's fallbacks only). flow: stage 1 from the flow
  // predictor (rollouts, options.predictor).
  SolveInfo step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                 Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, StepHistory& h, ContactReport& report,
                 bool flow) const;
  // Stages 1-2: Newton from the predicted guess (the history, or the flow predictor), then from the
  // velocity guess, then from q^{k,a} = q^k, and last (without constraints) by continuation in the
  // step length (step_continuation.hpp), stopping at the first that converges.
  SolveInfo free_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                      Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, StepHistory& h, bool flow) const;
  SolveInfo solve(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                  Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, MatX& lambda) const;
  // Stages 3-5 (contact_stages.cpp).
  SolveInfo contact_step(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& p, const Eigen::Ref<const MatX>& u,
                         Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next, StepHistory& h, ContactReport& report) const;
  // Stage 3: the gaps at q^{k+1} = qc.col(s); true (and z = the inactive solution) if none is negative.
  bool free_step_holds(IntegratorWorkspace& ws, const Eigen::Ref<const MatX>& qc, Eigen::Ref<VecX> z,
                       Eigen::Ref<VecX> phi) const;
  // The smallest gap of the contact points at configuration q.
  double smallest_gap(IntegratorWorkspace& ws, const Eigen::Ref<const VecX>& q) const;
  // Stage 4: the first root θ in (0, 1] of the smallest gap along the polynomial of qc (whose end is
  // below the terrain), or 0 if it starts there; then the step split at θ (refined by Newton on the
  // free piece's end: θ on exit), qc holding the free step's control points on entry and the
  // pieces' polynomial at the nodes on exit.
  double impact_time(IntegratorWorkspace& ws, const Eigen::Ref<const MatX>& qc) const;
  SolveInfo split_step(IntegratorWorkspace& ws, double& theta, const Eigen::Ref<const VecX>& p,
                       const Eigen::Ref<const MatX>& u, Eigen::Ref<MatX> qc, Eigen::Ref<VecX> p_next,
                       StepHistory& h, ContactReport& report) const;
  // Rollouts (rollout.cpp): the inputs checked and the record sized; step k's controls; a step recorded.
  void start_rollout(const VecX& q0, const VecX& p0, int N, const MatX& u, const StepHistory& start, Rollout& out,
                     bool hooked) const;
  void record_step(Rollout& out, int k, const SolveInfo& info, const Eigen::Ref<const MatX>& qc,
                   const Eigen::Ref<const VecX>& p_next) const;
  MatX lambda_guess(const MatX* lambda) const;
  void check_impulses(const VecX& z) const;  // InputError unless unknowns() finite numbers >= 0

  // A free base: the chart re-centred at q^k's attitude (θ^k = 0), p^k and the history's points
  // carried into it (StepHistory::centre).
  void recentre(IntegratorWorkspace& ws, Eigen::Ref<MatX> qc, StepHistory& h) const;
  // A free-base rollout's record in the public coordinates: q (N+1 x n, chart) with each row's
  // attitude (N+1 x 4 quaternions) -> q (N+1 x nq); p and contact.step_p to the base's frame.
  void public_record(Rollout& out, const MatX& attitude) const;
  // A free base's hook sees the public state: the chart q (any θ) about centre and p -> public, the
  // hook's call, and its p back into the chart.
  bool public_hook(StepHook& hook, int k, const VecX& q, const Mat3& centre, VecX& p, MatX& uk) const;
  // A free base's public q (nq) -> its chart q (n, θ = 0) and centre, ws.data's kinematics about it.
  std::pair<VecX, Mat3> chart_state(IntegratorWorkspace& ws, const VecX& q) const;

  Model model_;
  ContactModel contacts_;
  std::optional<FreeBase> free_base_;  // with a rotation chart
  ContactOptions contact_options_;
  Quadrature quad_;
  double dt_;
  MatX r_com_;         // 3 x C: the contact points in their body's COM frame
  MatX extrapolate_;   // E(b, a) - E(b, 0), E(b, a) = l_b(1 + c^a), a = 1..s: for guess_from_previous
  MatX extrapolate2_;  // (2s+1) x s, likewise for guess_from_history
  mutable WorkspacePool<IntegratorWorkspace> pool_;
};

}  // namespace hovi
