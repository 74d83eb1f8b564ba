"""Crocoddyl's box-FDDP on the pendulum, cart-pole and acrobot swing-ups: the reference side of the
FDDP comparison (hovi's FDDP is measured on the same optimal control problems).

The problems (the same for both solvers). State x = (q, v), N stages of dt = T / N, one control
vector held constant over each stage, start at rest hanging (q = 0, v = 0), box bounds |u| <= u_max,

    cost = sum_k dt R |u_k|^2  +  Wq |q_N - q_T|^2  +  Wv |v_N|^2          (R = 1, Wq = 1000, Wv = 100)

    pendulum   N = 40, T = 2.0, |u| <= 4,  q_T = [pi]        torque at joint 0
    cartpole   N = 50, T = 2.5, |u| <= 20, q_T = [0, pi]     force on the cart (joint 0)
    acrobot    N = 60, T = 4.0, |u| <= 15, q_T = [pi, 0]     torque at the elbow (joint 1)

(hovi.examples.swingups poses the same swing-ups with a final-state constraint and, for the cart-pole,
|cart| <= 1 m; box-FDDP takes neither: the final state is a penalty here and the cart is free.)

Crocoddyl side: the Pinocchio models below, built by hand from the numbers of
hovi.examples.models (bodies' inertia about their COM in the joint frame, as hovi takes it; the
test file checks mass matrices and forward dynamics against hovi's to 1e-12);
DifferentialActionModelFreeFwdDynamics (Pinocchio's ABA) integrated by IntegratedActionModelRK
(RK4, controls held over the stage); SolverBoxFDDP from us = 0 and xs = the rollout of us = 0 (which
is x0 repeated: hanging at rest is an equilibrium), th_stop 1e-10 on its stopping criterion
(|expected improvement|), at most 500 iterations. Every model is Crocoddyl's C++: no Python call per
stage. Actuation (Crocoddyl 3.2.1 has no matrix actuation model):

    pendulum   ActuationModelFull
    acrobot    ActuationModelFloatingBase, the shoulder joint named "root_joint": its DoF gets no
               torque, the control is the elbow torque (tau = [0, u]) -- exactly the acrobot
    cartpole   ActuationModelFull (u = [cart force, hinge torque]) with the hinge torque's bounds
               [0, 0]: the box-QP clamps it and the forward pass projects it onto 0, so it stays
               exactly 0 (its zero adds nothing to the control cost). ActuationModelFloatingBase
               leaves the *first* DoFs unactuated, the wrong end for the cart-pole.

Both tricks give bit-identical iterates (iterations, cost, xs, us) to tau = B u by a Python
ActuationModelAbstract subclass (build_problem(python_actuation=True), 3-4x slower); the test file
checks it. The problem runs on one thread (ShootingProblem.nthreads = 1; see build_problem).

Cost conventions: a Crocoddyl cost of weight w on a residual r is w * 0.5 * |r|^2 and RK4 multiplies
the running cost by dt (the terminal model's cost is not), hence control weight 2 R, state weights
2 Wq and 2 Wv.

    python bench/crocoddyl_baseline.py [--quick] [--only NAME ...]

Needs crocoddyl 3.2.1 with the libpinocchio its wheel was built against, 4.0.0 (pin==4.0.0): its
wheel does not pin it, and with pin 4.1.0 Crocoddyl reads Pinocchio's model with the wrong layout and
computes garbage dynamics silently. build_problem checks Crocoddyl's accelerations against
pinocchio.aba and raises CrocoddylPinocchioMismatch.

resim_error: the optimised controls re-simulated exactly (scipy DOP853, rtol = atol = 1e-12, on
Pinocchio's ABA, stage by stage with the held control) against the solver's knots: what RK4 at this
dt costs in accuracy. resimulate() is reused to measure hovi's trajectories the same way.
"""
from __future__ import annotations

import argparse
import time

import numpy as np

SWINGUPS = {
    # name: default N, T, control bound, target configuration
    "pendulum": dict(N=40, T=2.0, u_max=4.0, q_T=[np.pi]),
    "cartpole": dict(N=50, T=2.5, u_max=20.0, q_T=[0.0, np.pi]),
    "acrobot": dict(N=60, T=4.0, u_max=15.0, q_T=[np.pi, 0.0]),
}
GRAVITY = np.array([0.0, 0.0, -9.81])


# ----------------------------------------------------------------------------------------------
# The models: Pinocchio (by hand, from hovi.examples.models' numbers) and hovi's own
# ----------------------------------------------------------------------------------------------

def _rod_inertia(pin, length, mass):
    """hovi.examples.models._rod: a slender rod hanging along -z from its joint."""
    I = mass * length ** 2 / 12
    return pin.Inertia(mass, np.array([0.0, 0.0, -length / 2]), np.diag([I, I, 1e-4 * mass * length ** 2]))


def pinocchio_model(name: str):
    """The Pinocchio model of swing-up `name` (fixed base, gravity (0, 0, -9.81)), joints in hovi's
    order, every joint with nq = nv = 1 (so x = (q, v) as in hovi)."""
    import pinocchio as pin
    model = pin.Model()
    below = lambda dz: pin.SE3(np.eye(3), np.array([0.0, 0.0, -dz]))  # noqa: E731
    if name == "pendulum":  # models.pendulum(1): a uniform solid cylinder, 0.5 m, 1 kg, radius 0.02, about x
        length, mass, radius = 0.5, 1.0, 0.02
        I_t, I_a = mass * (3 * radius ** 2 + length ** 2) / 12, mass * radius ** 2 / 2
        j = model.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "joint1")
        model.appendBodyToJoint(j, pin.Inertia(mass, np.array([0.0, 0.0, -length / 2]), np.diag([I_t, I_t, I_a])),
                                pin.SE3.Identity())
    elif name == "acrobot":  # models.acrobot(): two 1 m, 1 kg rods about y
        length, mass = 1.0, 1.0
        # "root_joint": ActuationModelFloatingBase leaves this joint's DoF unactuated
        j1 = model.addJoint(0, pin.JointModelRY(), pin.SE3.Identity(), "root_joint")
        model.appendBodyToJoint(j1, _rod_inertia(pin, length, mass), pin.SE3.Identity())
        j2 = model.addJoint(j1, pin.JointModelRY(), below(length), "elbow")
        model.appendBodyToJoint(j2, _rod_inertia(pin, length, mass), pin.SE3.Identity())
    elif name == "cartpole":  # models.cartpole(): 1 kg cart on x, 0.3 kg 0.5 m pole about y
        cart_mass, pole_mass, pole_length = 1.0, 0.3, 0.5
        j1 = model.addJoint(0, pin.JointModelPX(), pin.SE3.Identity(), "slider")
        model.appendBodyToJoint(j1, pin.Inertia(cart_mass, np.zeros(3), np.eye(3) * 0.01 * cart_mass), pin.SE3.Identity())
        j2 = model.addJoint(j1, pin.JointModelRY(), pin.SE3.Identity(), "hinge")
        model.appendBodyToJoint(j2, _rod_inertia(pin, pole_length, pole_mass), pin.SE3.Identity())
    else:
        raise ValueError(f"unknown swing-up {name!r}; one of {sorted(SWINGUPS)}")
    model.gravity = pin.Motion(GRAVITY, np.zeros(3))
    return model


def actuation_matrix(name: str) -> np.ndarray:
    """B (n, m): tau = B u, as hovi's model.actuation."""
    return {"pendulum": np.array([[1.0]]), "acrobot": np.array([[0.0], [1.0]]),
            "cartpole": np.array([[1.0], [0.0]])}[name]


def hovi_model(name: str):
    """hovi's model of swing-up `name` (hovi.examples.models, the pendulum actuated at joint 0)."""
    from hovi.examples import models
    if name == "pendulum":
        m = models.pendulum(1)
        m.add_actuator(0)
        return m
    return {"acrobot": models.acrobot, "cartpole": models.cartpole}[name]()


# ----------------------------------------------------------------------------------------------
# The optimal control problem in Crocoddyl
# ----------------------------------------------------------------------------------------------

def _matrix_actuation(state, B):
    """tau = B u by a Python subclass of crocoddyl.ActuationModelAbstract: Python on every stage's
    calc and calcDiff (slow). Only the reference that the built-in actuations above are checked
    against (build_problem(..., python_actuation=True))."""
    import crocoddyl

    class ActuationModelMatrix(crocoddyl.ActuationModelAbstract):
        def __init__(self):
            crocoddyl.ActuationModelAbstract.__init__(self, state, B.shape[1])

        def calc(self, data, x, u):
            data.tau[:] = B @ u

        def calcDiff(self, data, x, u):
            dtau_du = data.dtau_du  # eigenpy hands an (n, 1) matrix over as a 1-D view
            dtau_du[...] = B.reshape(dtau_du.shape)

    return ActuationModelMatrix()


def build_problem(name: str, N: int | None = None, T: float | None = None, *, Wq: float = 1000.0,
                  Wv: float = 100.0, R: float = 1.0, u_max: float | None = None, q_T=None,
                  python_actuation: bool = False, nthreads: int = 1):
    """(crocoddyl.ShootingProblem, info) for swing-up `name`; info: N, T, dt, x0, B, nu (the number
    of Crocoddyl controls: for the cart-pole 2, its second, the hinge torque, held at 0 by its bounds).
    python_actuation: tau = B u by a Python actuation model instead (slow; a reference for tests).
    nthreads: the problem's OpenMP threads over the stages (Crocoddyl's default is all cores; on a
    busy machine its barriers then cost milliseconds per pass: 0.73 s instead of 0.022 s for the
    pendulum with a compiler on the other core). 1: one core, as hovi's solver."""
    import crocoddyl
    spec = SWINGUPS[name]
    N = int(spec["N"] if N is None else N)
    T = float(spec["T"] if T is None else T)
    u_max = float(spec["u_max"] if u_max is None else u_max)
    q_T = np.asarray(spec["q_T"] if q_T is None else q_T, dtype=float)
    dt = T / N
    pm = pinocchio_model(name)
    n = pm.nv
    state = crocoddyl.StateMultibody(pm)
    if python_actuation:
        actuation = _matrix_actuation(state, actuation_matrix(name))
        lb, ub = np.full(actuation.nu, -u_max), np.full(actuation.nu, u_max)
    elif name == "acrobot":
        actuation = crocoddyl.ActuationModelFloatingBase(state)
        lb, ub = np.full(1, -u_max), np.full(1, u_max)
    elif name == "cartpole":
        actuation = crocoddyl.ActuationModelFull(state)
        lb, ub = np.array([-u_max, 0.0]), np.array([u_max, 0.0])  # the hinge torque pinned to 0
    else:
        actuation = crocoddyl.ActuationModelFull(state)
        lb, ub = np.full(1, -u_max), np.full(1, u_max)
    nu = actuation.nu
    assert nu == lb.size

    running_costs = crocoddyl.CostModelSum(state, nu)
    # w * 0.5 |u|^2 per unit time, times dt by the integrator: w = 2 R
    running_costs.addCost("control", crocoddyl.CostModelResidual(state, crocoddyl.ResidualModelControl(state, nu)), 2 * R)
    terminal_costs = crocoddyl.CostModelSum(state, nu)
    x_T = np.concatenate([q_T, np.zeros(n)])
    weights = np.concatenate([np.full(n, 2 * Wq), np.full(n, 2 * Wv)])  # 0.5 sum w_i r_i^2
    terminal_costs.addCost("final_state", crocoddyl.CostModelResidual(
        state, crocoddyl.ActivationModelWeightedQuad(weights), crocoddyl.ResidualModelState(state, x_T, nu)), 1.0)

    def integrated(costs, step):
        dam = crocoddyl.DifferentialActionModelFreeFwdDynamics(state, actuation, costs)
        dam.u_lb, dam.u_ub = lb, ub
        iam = crocoddyl.IntegratedActionModelRK(dam, crocoddyl.RKType.four, step)
        iam.u_lb, iam.u_ub = lb, ub
        return iam

    running = integrated(running_costs, dt)
    terminal = integrated(terminal_costs, 0.0)  # the terminal model's calc(x) is its cost alone
    _check_dynamics(name, running.differential, lb.size)
    x0 = np.zeros(2 * n)
    problem = crocoddyl.ShootingProblem(x0, [running] * N, terminal)
    if problem.nthreads != int(nthreads):  # (setting it can print a warning on stderr)
        problem.nthreads = int(nthreads)
    return problem, dict(N=N, T=T, dt=dt, x0=x0, B=actuation_matrix(name), nu=nu, u_max=u_max, q_T=q_T,
                         Wq=Wq, Wv=Wv, R=R)


class CrocoddylPinocchioMismatch(RuntimeError):
    """Crocoddyl's dynamics disagree with Pinocchio's own: the libcrocoddyl binary and the installed
    libpinocchio are not ABI-compatible."""


def _check_dynamics(name, dam, nu):
    """Crocoddyl's forward dynamics at one generic state against pinocchio.aba called from Python.
    The crocoddyl 3.2.1 wheels are built against libpinocchio 4.0.0 but do not pin it; with pin 4.1.0
    Crocoddyl reads Pinocchio's model and data with the wrong layout and returns garbage, silently."""
    import crocoddyl
    import pinocchio as pin
    pm = pinocchio_model(name)
    n = pm.nv
    x = np.linspace(0.3, 1.1, 2 * n)
    u = np.linspace(0.7, -0.4, nu) if nu == actuation_matrix(name).shape[1] else np.array([0.7, 0.0])
    data = dam.createData()
    dam.calc(data, x, u)
    tau = actuation_matrix(name) @ u[:actuation_matrix(name).shape[1]]
    expected = pin.aba(pm, pm.createData(), x[:n], x[n:], tau)
    if not np.allclose(data.xout, expected, rtol=1e-10, atol=1e-10):
        raise CrocoddylPinocchioMismatch(
            f"crocoddyl {crocoddyl.__version__} computes accelerations {np.asarray(data.xout)} where Pinocchio "
            f"{pin.__version__} gives {expected} ({name}): the libcrocoddyl binary was built against another "
            "libpinocchio (the crocoddyl 3.2.1 wheels: libpinocchio 4.0.0; pip install pin==4.0.0)")


def cost_formula(xs, us, dt, q_T, *, Wq=1000.0, Wv=100.0, R=1.0) -> float:
    """sum_k dt R |u_k|^2 + Wq |q_N - q_T|^2 + Wv |v_N|^2 from knots xs (N+1, 2n) and controls us (N, m)."""
    xs, us = np.asarray(xs, dtype=float), np.asarray(us, dtype=float)
    n = xs.shape[1] // 2
    return float(dt * R * np.sum(us ** 2) + Wq * np.sum((xs[-1, :n] - q_T) ** 2) + Wv * np.sum(xs[-1, n:] ** 2))


# ----------------------------------------------------------------------------------------------
# Re-simulation of held controls (scipy DOP853 on Pinocchio's ABA)
# ----------------------------------------------------------------------------------------------

class _ABA:
    def __init__(self, name):
        import pinocchio as pin
        self.pin = pin
        self.model = pinocchio_model(name)
        self.data = self.model.createData()
        self.B = actuation_matrix(name)
        self.n = self.model.nv

    def xdot(self, x, tau):
        q, v = x[:self.n], x[self.n:]
        return np.concatenate([v, self.pin.aba(self.model, self.data, q, v, tau)])

    def mass_matrix(self, q):
        M = self.pin.crba(self.model, self.data, np.asarray(q, dtype=float))
        return np.triu(M) + np.triu(M, 1).T


def resimulate(model_name: str, x0, us, dt: float, *, rtol: float = 1e-12, atol: float = 1e-12) -> np.ndarray:
    """The trajectory (N+1, 2n) of x = (q, v) from x0 under the controls us (N, m), each held over
    its stage of length dt (tau = B u_k), integrated stage by stage by scipy's DOP853 (rtol, atol)
    on Pinocchio's ABA. For hovi's (q, p) states convert x0 first: hovi_state_to_x."""
    from scipy.integrate import solve_ivp
    f = _ABA(model_name)
    us = np.asarray(us, dtype=float).reshape(len(us), -1)
    if us.shape[1] != f.B.shape[1]:
        raise ValueError(f"{model_name}: us has {us.shape[1]} columns, the model {f.B.shape[1]} controls")
    xs = np.empty((len(us) + 1, 2 * f.n))
    xs[0] = np.asarray(x0, dtype=float)
    for k, u in enumerate(us):
        tau = f.B @ u
        sol = solve_ivp(lambda t, x: f.xdot(x, tau), (0.0, dt), xs[k], method="DOP853", rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"{model_name}: DOP853 failed on stage {k}: {sol.message}")
        xs[k + 1] = sol.y[:, -1]
    return xs


def hovi_state_to_x(model_name: str, q, p) -> np.ndarray:
    """hovi's state (q, p) -> x = (q, v), v = M(q)^-1 p (Pinocchio's CRBA); q, p (n,) -> (2n,),
    or (K, n) -> (K, 2n)."""
    f = _ABA(model_name)
    q, p = np.asarray(q, dtype=float), np.asarray(p, dtype=float)
    Q, P = q.reshape(-1, f.n), p.reshape(-1, f.n)
    x = np.hstack([Q, np.array([np.linalg.solve(f.mass_matrix(qk), pk) for qk, pk in zip(Q, P)])])
    return x[0] if q.ndim == 1 else x


def resim_errors(model_name: str, xs, us, dt: float) -> tuple[float, float]:
    """(max over knots, final knot) of |x_resim,k - xs_k|_inf, the re-simulation from xs[0]."""
    xs = np.asarray(xs, dtype=float)
    err = np.abs(resimulate(model_name, xs[0], us, dt) - xs).max(axis=1)
    return float(err.max()), float(err[-1])


# ----------------------------------------------------------------------------------------------
# The solve
# ----------------------------------------------------------------------------------------------

def solve_swingup(name: str, N: int | None = None, T: float | None = None, *, Wq: float = 1000.0,
                  Wv: float = 100.0, R: float = 1.0, max_iter: int = 500, repeats: int = 1,
                  th_stop: float = 1e-10, python_actuation: bool = False, nthreads: int = 1) -> dict:
    """Crocoddyl's SolverBoxFDDP on swing-up `name` from us = 0, xs = its rollout (x0 repeated).

    Returns solve_seconds (best of `repeats` solver.solve calls, each by a fresh solver from the
    same initial guess), setup_seconds (models, problem and solver built once), iterations (the
    backward passes; Crocoddyl's solver.iter is the index of the last one when converged), cost,
    converged (the solver stopped by its criterion, stop < th_stop, not by max_iter nor by maximal
    regularisation), stop (its last criterion value), xs (N+1, 2n), us (N, m: hovi's controls; the
    cart-pole's pinned hinge torque dropped), resim_error (max over knots of |x_resim - xs|_inf, see
    resimulate) and resim_final_error (the same at the last knot), N, T, dt."""
    import crocoddyl
    t0 = time.perf_counter()
    problem, info = build_problem(name, N, T, Wq=Wq, Wv=Wv, R=R, python_actuation=python_actuation,
                                  nthreads=nthreads)
    solver = crocoddyl.SolverBoxFDDP(problem)
    setup_seconds = time.perf_counter() - t0
    us0 = [np.zeros(info["nu"])] * info["N"]
    xs0 = problem.rollout(us0)
    best = np.inf
    for r in range(max(1, int(repeats))):
        if r:
            solver = crocoddyl.SolverBoxFDDP(problem)
        solver.th_stop = th_stop
        t = time.perf_counter()
        converged = solver.solve(xs0, us0, max_iter, True)
        best = min(best, time.perf_counter() - t)
    xs = np.array(solver.xs)
    us_full = np.array(solver.us)
    us = us_full
    if info["nu"] != info["B"].shape[1]:  # the cart-pole: back to its one control, the cart force
        assert np.all(us_full[:, 1] == 0.0), "the pinned hinge torque moved"
        us = us_full[:, :1]
    err, final_err = resim_errors(name, xs, us, info["dt"])
    return dict(name=name, N=info["N"], T=info["T"], dt=info["dt"], solve_seconds=best, setup_seconds=setup_seconds,
                iterations=int(solver.iter) + int(converged), cost=float(solver.cost), converged=bool(converged),
                stop=float(solver.stop), xs=xs, us=us, resim_error=err, resim_final_error=final_err)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="one solve per swing-up (the default: best of 5)")
    ap.add_argument("--only", nargs="+", choices=sorted(SWINGUPS), default=list(SWINGUPS))
    args = ap.parse_args()
    import crocoddyl
    print(f"Crocoddyl {crocoddyl.__version__} SolverBoxFDDP, RK4, from us = 0; th_stop 1e-10, at most 500 iterations")
    print(f"{'swing-up':9} {'N':>3} {'T':>4} {'iter':>5} {'conv':>5} {'cost':>12} {'|q_N-q_T|':>10} "
          f"{'resim err':>10} {'final err':>10} {'solve s':>9} {'setup s':>8}")
    for name in args.only:
        r = solve_swingup(name, repeats=1 if args.quick else 5)
        n = r["xs"].shape[1] // 2
        miss = np.abs(r["xs"][-1, :n] - np.asarray(SWINGUPS[name]["q_T"])).max()
        print(f"{name:9} {r['N']:3d} {r['T']:4.1f} {r['iterations']:5d} {str(r['converged']):>5} {r['cost']:12.6f} "
              f"{miss:10.2e} {r['resim_error']:10.2e} {r['resim_final_error']:10.2e} {r['solve_seconds']:9.4f} "
              f"{r['setup_seconds']:8.4f}")


if __name__ == "__main__":
    main()
