"""A CasADi baseline for hovi's trajectory optimisation: the pendulum, cart-pole and acrobot
swing-ups of hovi.examples.swingups transcribed by hand with Hermite-Simpson collocation in CasADi,
exact Hessian (CasADi's default), solved by IPOPT, timed in the same process as hovi.

The problems are hovi's own: T, N, the control and configuration bounds, the fixed initial and final
states are read from the hovi.trajopt.Problem that hovi.examples.swingups builds (cost: ∫ |u|² dt,
hovi's ControlEffort(1)). Only the dynamics are written again, here, as CasADi SX expressions:

    pendulum   a uniform solid cylinder (0.5 m, 1 kg, radius 0.02 m) about a horizontal axis
    acrobot    two slender rods (1 m, 1 kg, inertia m L²/12 about the COM), elbow torque only
    cartpole   a 1 kg cart on a rail, a 0.3 kg 0.5 m slender-rod pole, the force on the cart

From the Lagrangian L = T - V (T from the links' centres-of-mass velocities and angular rates, V =
m g z of the COMs, g = 9.81) CasADi differentiates the equations of motion M(q) q̈ + C(q, q̇) q̇ + G(q)
= B u with M = ∂²T/∂q̇², C q̇ = (∂(M q̇)/∂q) q̇ - ∂T/∂q, G = ∂V/∂q, and q̈ = M⁻¹ (B u - C q̇ - G)
(casadi.solve, symbolic). tests/test_casadi_baseline.py checks q̈ against hovi's
Model.forward_dynamics(q, q̇, B u) (articulated-body algorithm) to 1e-12 at random states.

Transcription: Hermite-Simpson in the *separated* form. Points j = 0..2N, even j the knots, odd j
the interval midpoints; the state x = (q, q̇) and the control u are variables at every point (the
same variables as hovi's HermiteSimpson with controls='per_point'; u(t) is the quadratic through
the knot, midpoint and knot values of each interval: piecewise quadratic, continuous). On each
interval k, with f_j = (q̇_j, q̈(x_j, u_j)) and h = T / N:

    x_{2k+1} = (x_{2k} + x_{2k+2}) / 2 + h / 8 (f_{2k} - f_{2k+2})        (Hermite interpolation)
    x_{2k+2} = x_{2k} + h / 6 (f_{2k} + 4 f_{2k+1} + f_{2k+2})            (Simpson quadrature)
    cost    += h / 6 (|u_{2k}|² + 4 |u_{2k+1}|² + |u_{2k+2}|²)            (Simpson, as hovi's samples)

Bounds on u and q at every point (the cart within ±1 m), the initial and final states fixed as
bounds (lbx = ubx: IPOPT makes them parameters, as for hovi). One casadi.nlpsol('ipopt') on SX
expressions (the dynamics Function mapped over the 2N + 1 points), exact Hessian of the
Lagrangian, IPOPT options as hovi's DEFAULT_OPTIONS except the Hessian: tol 1e-8, constr_viol_tol
1e-10, bound_relax_factor 0, acceptable_iter 0, mu_strategy adaptive, max_iter 3000, print_level
0, linear_solver mumps. CasADi's wheel bundles its own IPOPT (3.14.x) with MUMPS; hovi is built
against the system IPOPT (Debian's 3.11.9 with MUMPS 5.5): ipopt_versions().

Reported per solve: set-up seconds (the SX or MX graph of the transcription and casadi.nlpsol, which
builds the Jacobian and Hessian functions; SX, the default, builds them as SX graphs up front,
MX keeps the mapped dynamics as a call and differentiates at run time: cheaper set-up, slower
evaluations; both are run, the faster is the baseline), the IPOPT phase (wall time of the solver call, and
CasADi's own t_wall_total), iterations, cost, success, and the one-interval error: from every
knot, the ODE integrated over one interval with the solution's u(t) (scipy DOP853, rtol = atol =
1e-12, on hovi's forward dynamics) against the solution's next knot, the max over intervals of the
inf norm over (q, q̇). one_interval_error() measures hovi's solutions the same way (their knot
velocities M(q)⁻¹ p for the VI, u(t) from Result.control_function()). hovi is run with the guess
bench/trajopt.py gives it (GUESSES), CasADi from the same guess; each time is the fastest of
--repeat identical solves, after one small warm-up solve on each side (plugin loading).

Cost error: against a reference optimum, this transcription at N_ref = 16 x the largest N,
warm-started from the solution at that N (so it refines the same local optimum), cross-checked
against hovi's VI s = 3 at 4 x that N.

    python bench/casadi_baseline.py [--quick] [--no-hovi] [--lbfgs] [--repeat R] [--reuse-references]
                                    [--only pendulum cartpole acrobot]

Writes bench/results/casadi_baseline.json (casadi_baseline_quick.json with --quick).
"""
from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

import numpy as np

from common import study_parser

try:
    import casadi as ca
except ImportError:  # pragma: no cover - bench-only dependency
    ca = None

G = 9.81

# hovi's IPOPT options (hovi.trajopt.solvers.ipopt.DEFAULT_OPTIONS) but the exact Hessian, for CasADi's IPOPT
IPOPT_OPTIONS = {
    "tol": 1e-8,
    "constr_viol_tol": 1e-10,
    "bound_relax_factor": 0.0,
    "acceptable_iter": 0,
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    "mu_strategy": "adaptive",
    "linear_solver": "mumps",
    "hessian_approximation": "exact",
}

# nominal (coarse) and fine N of the comparison (CasADi's N = 80 / 80 / 160)
GRIDS = {"pendulum": (40, 80), "cartpole": (50, 80), "acrobot": (60, 160)}
# hovi's guess for each swing-up in bench/trajopt.py: the rollout of zero controls (the hanging rest:
# an equilibrium, so the initial state held) or, for the acrobot, the straight line from q0 to qT
GUESSES = {"pendulum": "rollout", "cartpole": "rollout", "acrobot": "linear"}


def _require_casadi():
    if ca is None:
        raise ImportError("bench/casadi_baseline.py needs casadi: pip install casadi (requirements-dev.txt)")


# --------------------------------------------------------------------------------------------------
# dynamics: a planar Lagrangian per model
# --------------------------------------------------------------------------------------------------

def _planar_links(name, q):
    """[(mass, inertia about the COM, COM (horizontal, vertical) as SX, angle as SX)] of each body."""
    s, c = ca.sin, ca.cos
    if name == "pendulum":
        L, m, r = 0.5, 1.0, 0.02                      # models.pendulum(1): a solid cylinder about x
        return [(m, m * (3 * r * r + L * L) / 12, (L / 2 * s(q[0]), -L / 2 * c(q[0])), q[0])]
    if name == "acrobot":
        L, m = 1.0, 1.0                                # models.acrobot(): slender rods about y
        I = m * L * L / 12
        a1, a2 = q[0], q[0] + q[1]
        elbow = (-L * s(a1), -L * c(a1))
        return [(m, I, (-L / 2 * s(a1), -L / 2 * c(a1)), a1),
                (m, I, (elbow[0] - L / 2 * s(a2), elbow[1] - L / 2 * c(a2)), a2)]
    if name == "cartpole":
        mc, mp, L = 1.0, 0.3, 0.5                      # models.cartpole(): the cart slides along x
        return [(mc, 0.0, (q[0], 0.0 * q[0]), 0.0 * q[0]),
                (mp, mp * L * L / 12, (q[0] - L / 2 * s(q[1]), -L / 2 * c(q[1])), q[1])]
    raise ValueError(f"unknown swing-up {name!r}")


ACTUATION = {"pendulum": np.array([[1.0]]), "acrobot": np.array([[0.0], [1.0]]), "cartpole": np.array([[1.0], [0.0]])}


def dynamics(name: str):
    """casadi.Function qdd(q, qd, u) (SX) of the swing-up's model: q̈ = M⁻¹ (B u - C q̇ - G)."""
    _require_casadi()
    B = ACTUATION[name]
    n, m = B.shape
    q, qd, u = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("u", m)
    T, V = 0, 0
    for mass, inertia, (x, z), angle in _planar_links(name, q):
        vx, vz, w = ca.jtimes(x, q, qd), ca.jtimes(z, q, qd), ca.jtimes(angle, q, qd)
        T += 0.5 * mass * (vx ** 2 + vz ** 2) + 0.5 * inertia * w ** 2
        V += mass * G * z
    M = ca.hessian(T, qd)[0]
    p = ca.gradient(T, qd)
    Cqd = ca.jtimes(p, q, qd) - ca.gradient(T, q)
    rhs = ca.mtimes(ca.DM(B), u) - Cqd - ca.gradient(V, q)
    qdd = ca.solve(M, rhs) if n > 1 else rhs / M
    return ca.Function(f"{name}_qdd", [q, qd, u], [ca.simplify(qdd) if n == 1 else qdd], ["q", "qd", "u"], ["qdd"])


# --------------------------------------------------------------------------------------------------
# the swing-ups as hovi defines them
# --------------------------------------------------------------------------------------------------

@dataclass
class Swingup:
    """The data of hovi.examples.swingups' problem NAME at N."""
    name: str
    N: int
    T: float
    q0: np.ndarray
    qd0: np.ndarray
    qT: np.ndarray
    qdT: np.ndarray
    q_lower: np.ndarray
    q_upper: np.ndarray
    u_lower: np.ndarray
    u_upper: np.ndarray
    hovi_problem: object = field(repr=False, default=None)

    @property
    def h(self) -> float:
        return self.T / self.N


def swingup(name: str, N: int | None = None) -> Swingup:
    """hovi.examples.swingups' NAME swing-up (its default N unless given) as plain arrays."""
    from hovi.examples import swingups
    prob = swingups.EXAMPLES[name]() if N is None else swingups.EXAMPLES[name](N=N)
    assert len(prob.costs) == 1 and type(prob.costs[0]).__name__ == "ControlEffort" and prob.costs[0].weight == 1.0
    assert prob.controls == "per_point" and not prob.model.n_constraints
    arr = lambda a: np.array(a, dtype=float)
    return Swingup(name, prob.N, float(prob.T), arr(prob.q0), arr(prob.qdot0), arr(prob.qT), arr(prob.qdotT),
                   arr(prob.q_lower), arr(prob.q_upper), arr(prob.u_lower), arr(prob.u_upper), prob)


# --------------------------------------------------------------------------------------------------
# Hermite-Simpson in CasADi
# --------------------------------------------------------------------------------------------------

@dataclass
class Solution:
    name: str
    N: int
    T: float
    success: bool
    status: str
    iterations: int
    cost: float
    setup_seconds: float
    ipopt_seconds: float
    casadi_t_wall_total: float
    q: np.ndarray          # (2N + 1, n) at knots and midpoints
    qd: np.ndarray         # (2N + 1, n)
    u: np.ndarray          # (2N + 1, m)
    w: np.ndarray = field(repr=False, default=None)

    def control_function(self):
        """u(t), vectorised (t (K,) -> (K, m)): the quadratic through each interval's knot, midpoint, knot."""
        return piecewise_quadratic(self.T, self.N, self.u)

    def knots(self):
        """(t (N + 1,), q (N + 1, n), q̇ (N + 1, n)) at the knots."""
        return np.arange(self.N + 1) * self.T / self.N, self.q[::2], self.qd[::2]

    def as_guess(self):
        """(q(t), q̇(t), u(t)) of this solution, each the quadratic through knot, midpoint and knot values
        (a warm start for another N, or for hovi: ``trajopt.solve(..., guess=sol.as_guess())``)."""
        return tuple(piecewise_quadratic(self.T, self.N, V) for V in (self.q, self.qd, self.u))


def piecewise_quadratic(T, N, V):
    """f(t), vectorised (t (K,) -> (K, d)): on interval k the quadratic through V[2k], V[2k+1], V[2k+2]
    (values (2N + 1, d) at knots and midpoints)."""
    h = T / N

    def f(t):
        t = np.atleast_1d(np.asarray(t, float))
        k = np.clip(np.floor(t / h).astype(int), 0, N - 1)
        x = t / h - k
        b = np.stack([2 * (x - 0.5) * (x - 1), -4 * x * (x - 1), 2 * x * (x - 0.5)], 1)
        return np.einsum("ka,kad->kd", b, np.stack([V[2 * k], V[2 * k + 1], V[2 * k + 2]], 1))
    return f


def build(name: str, N: int | None = None, ipopt_options: dict | None = None, graph: str = "sx"):
    """(solver, bounds dict, layout, Swingup): the CasADi Hermite-Simpson NLP of the swing-up and its IPOPT.

    graph 'sx' (the default, the baseline): the whole NLP as one SX expression graph, CasADi's fastest
    evaluation (its derivatives are SX graphs too, built when nlpsol is created); 'mx': the SX dynamics
    Function mapped over the points inside an MX graph (cheaper set-up, derivatives by MX AD at run time)."""
    _require_casadi()
    sw = swingup(name, N)
    f = dynamics(name)
    n, m = ACTUATION[name].shape
    N, h, P = sw.N, sw.h, 2 * sw.N + 1
    nx = 2 * n
    if graph not in ("sx", "mx"):
        raise ValueError(f"graph must be 'sx' or 'mx', got {graph!r}")
    W = (ca.SX if graph == "sx" else ca.MX).sym("w", nx + m, P)        # column j: (q_j, q̇_j, u_j)
    X, U = W[:nx, :], W[nx:, :]
    qdd = f.map(P)(X[:n, :], X[n:, :], U)
    F = ca.vertcat(X[n:, :], qdd)         # (2n, P)
    a, mid, b = slice(0, P - 2, 2), slice(1, P - 1, 2), slice(2, P, 2)
    hermite = X[:, mid] - (0.5 * (X[:, a] + X[:, b]) + h / 8 * (F[:, a] - F[:, b]))
    simpson = X[:, b] - X[:, a] - h / 6 * (F[:, a] + 4 * F[:, mid] + F[:, b])
    g = ca.vec(ca.vertcat(hermite, simpson))
    usq = ca.sum1(U * U)
    cost = h / 6 * (ca.sum2(usq[:, a]) + 4 * ca.sum2(usq[:, mid]) + ca.sum2(usq[:, b]))
    lb = np.zeros((nx + m, P))
    ub = np.zeros((nx + m, P))
    lb[:n], ub[:n] = sw.q_lower[:, None], sw.q_upper[:, None]
    lb[n:nx], ub[n:nx] = -np.inf, np.inf
    lb[nx:], ub[nx:] = sw.u_lower[:, None], sw.u_upper[:, None]
    lb[:n, 0] = ub[:n, 0] = sw.q0
    lb[n:nx, 0] = ub[n:nx, 0] = sw.qd0
    lb[:n, -1] = ub[:n, -1] = sw.qT
    lb[n:nx, -1] = ub[n:nx, -1] = sw.qdT
    opts = {"ipopt": {**IPOPT_OPTIONS, **(ipopt_options or {})}, "print_time": False, "record_time": True}
    solver = ca.nlpsol(f"hs_{name}_{N}", "ipopt", {"x": ca.vec(W), "f": cost, "g": g}, opts)
    bounds = {"lbx": lb.ravel(order="F"), "ubx": ub.ravel(order="F"), "lbg": 0.0, "ubg": 0.0}
    return solver, bounds, (n, m, P), sw


def guess_vector(sw: Swingup, guess, n, m, P):
    """w0 (column-major (2n + m, P)) from 'rollout' (the initial state held, zero controls: hovi's
    rollout of zero controls from these equilibria), 'linear' (hovi's straight line: q from q0 to qT,
    q̇ = (qT - q0) / T, zero controls), or (q(t), q̇(t), u(t)) functions."""
    t = np.arange(P) * sw.h / 2
    if isinstance(guess, str) and guess == "rollout":
        q, qd, u = np.tile(sw.q0, (P, 1)), np.tile(sw.qd0, (P, 1)), np.zeros((P, m))
    elif isinstance(guess, str) and guess == "linear":
        q = sw.q0 + np.outer(t / sw.T, sw.qT - sw.q0)
        qd, u = np.tile((sw.qT - sw.q0) / sw.T, (P, 1)), np.zeros((P, m))
    else:
        q, qd, u = (np.asarray(fn(t), float).reshape(P, -1) for fn in guess)
    return np.hstack([q, qd, u]).T.ravel(order="F")


def solve(name: str, N: int | None = None, guess="auto", ipopt_options: dict | None = None,
          graph: str = "sx") -> Solution:
    """Build and solve the CasADi Hermite-Simpson swing-up; set-up and IPOPT phase timed apart. guess:
    'auto' (GUESSES: hovi's guess in bench/trajopt.py), 'rollout', 'linear' or (q(t), q̇(t), u(t))."""
    t0 = time.perf_counter()
    solver, bounds, (n, m, P), sw = build(name, N, ipopt_options, graph)
    setup = time.perf_counter() - t0
    w0 = np.clip(guess_vector(sw, GUESSES[name] if isinstance(guess, str) and guess == "auto" else guess, n, m, P),
                 bounds["lbx"], bounds["ubx"])
    t1 = time.perf_counter()
    out = solver(x0=w0, **bounds)
    ipopt = time.perf_counter() - t1
    st = solver.stats()
    w = np.array(out["x"]).ravel()
    Wm = w.reshape((2 * n + m, P), order="F")
    return Solution(name, sw.N, sw.T, bool(st["success"]), str(st["return_status"]), int(st["iter_count"]),
                    float(out["f"]), setup, ipopt, float(st.get("t_wall_total", np.nan)),
                    Wm[:n].T.copy(), Wm[n:2 * n].T.copy(), Wm[2 * n:].T.copy(), w)


# --------------------------------------------------------------------------------------------------
# accuracy
# --------------------------------------------------------------------------------------------------

def one_interval_error(model, B, t_knots, q_knots, qd_knots, u_of_t, rtol=1e-12, atol=1e-12):
    """max over intervals k of |x(t_{k+1}) - x_{k+1}|_inf, x(t) the ODE q̈ = FD(q, q̇, B u(t)) (hovi's
    forward dynamics) from the knot state x_k = (q_k, q̇_k) over one interval (scipy DOP853). u(t) is
    evaluated strictly inside each interval (a per-stage polynomial may jump at a knot)."""
    from scipy.integrate import solve_ivp
    n = q_knots.shape[1]
    B = np.asarray(B, float)
    worst = 0.0
    for k in range(len(t_knots) - 1):
        ta, tb = float(t_knots[k]), float(t_knots[k + 1])
        eps = 1e-12 * (tb - ta)

        def rhs(t, x):
            u = np.asarray(u_of_t(np.array([min(max(t, ta + eps), tb - eps)])), float).ravel()
            return np.concatenate([x[n:], model.forward_dynamics(x[:n], x[n:], B @ u)])
        sol = solve_ivp(rhs, (ta, tb), np.concatenate([q_knots[k], qd_knots[k]]), method="DOP853", rtol=rtol, atol=atol)
        if not sol.success:
            return float("nan")
        worst = max(worst, float(np.abs(sol.y[:, -1] - np.concatenate([q_knots[k + 1], qd_knots[k + 1]])).max()))
    return worst


def casadi_one_interval_error(sol: Solution) -> float:
    sw = swingup(sol.name, sol.N)
    t, q, qd = sol.knots()
    return one_interval_error(sw.hovi_problem.model, ACTUATION[sol.name], t, q, qd, sol.control_function())


def hovi_knots(result, model):
    """(t, q, q̇) at the knots of a hovi trajopt Result: Hermite-Simpson's q, v at the even points;
    the VI's q at the knots and q̇ = M(q)⁻¹ p of its discrete momenta."""
    tr = result.trajectory
    if "p" in tr:
        t = np.asarray(tr["t_knots"])
        stride = (len(tr["t"]) - 1) // (len(t) - 1)
        q = np.asarray(tr["q"])[::stride]
        qd = np.array([np.linalg.solve(model.mass_matrix(qk), pk) for qk, pk in zip(q, np.asarray(tr["p"]))])
        return t, q, qd
    t = np.asarray(tr["t"])
    stride = 2
    return t[::stride], np.asarray(tr["q"])[::stride], np.asarray(tr["v"])[::stride]


def hovi_one_interval_error(result, name: str) -> float:
    prob = result.transcription.problem
    t, q, qd = hovi_knots(result, prob.model)
    return one_interval_error(prob.model, prob.model.actuation, t, q, qd, result.control_function())


def reference(name: str, N_ref: int, guess_solution: Solution):
    """The reference optimum: this Hermite-Simpson at N_ref warm-started from guess_solution (the same
    local optimum, refined), and hovi's VI s = 3 at N_ref / 4 warm-started from it (a cross-check)."""
    from hovi import trajopt
    from hovi.examples import swingups
    ref = solve(name, N_ref, guess=guess_solution.as_guess())
    vi = trajopt.solve(swingups.EXAMPLES[name](N=N_ref // 4), trajopt.VI(s=3), verbose=False,
                       guess=ref.as_guess(), hessian="fd")
    return {"cost": ref.cost, "N": N_ref, "success": ref.success, "iterations": ref.iterations,
            "vi3_N": N_ref // 4, "vi3_cost": vi.cost, "vi3_success": bool(vi.success),
            "relative_difference": abs(vi.cost - ref.cost) / abs(ref.cost)}


# --------------------------------------------------------------------------------------------------
# the comparison
# --------------------------------------------------------------------------------------------------

def ipopt_versions() -> dict:
    """The IPOPT behind each side (CasADi's bundled library, the one hovi was built against) and their
    linear solver."""
    from hovi.trajopt.solvers.ipopt import ipopt_version
    out = {"casadi": ca.__version__ if ca is not None else None, "hovi_ipopt": ipopt_version()}
    if ca is not None:
        import glob
        import os
        libs = glob.glob(os.path.join(os.path.dirname(ca.__file__), "libipopt.so.*.*"))
        out["casadi_ipopt"] = libs[0].rsplit("libipopt.so.", 1)[1] if libs else None
    out["linear_solver"] = "MUMPS on both sides (hovi: IPOPT's default, the system MUMPS 5.5; CasADi: linear_solver mumps, its bundled MUMPS)"
    return out


def casadi_row(sol: Solution, ref_cost: float, graph: str = "sx") -> dict:
    return {"solver": f"CasADi HS ({graph.upper()})", "N": sol.N, "success": sol.success, "status": sol.status,
            "iterations": sol.iterations, "cost": sol.cost, "cost_error": abs(sol.cost - ref_cost) / abs(ref_cost),
            "setup_seconds": sol.setup_seconds, "ipopt_seconds": sol.ipopt_seconds,
            "solve_seconds": sol.setup_seconds + sol.ipopt_seconds, "casadi_t_wall_total": sol.casadi_t_wall_total,
            "one_interval_error": casadi_one_interval_error(sol) if sol.success else float("nan")}


HOVI_METHODS = [("VI s=1", "vi", 1), ("VI s=2", "vi", 2), ("VI s=3", "vi", 3), ("VI s=4", "vi", 4), ("VI s=5", "vi", 5),
                ("HS implicit", "hs", 2)]


def hovi_row(name, N, label, kind, s, ref_cost, hessian="auto", repeat=1, continuation=True):
    """hovi's solve of the swing-up at N, timed from building the Problem to the Result: set-up
    (everything outside IPOPT's solve call: transcription, NLP, guess, the 'fd' Hessian's pattern, the
    Result's trajectory) and the IPOPT phase (Result.wall_seconds) apart; the fastest of ``repeat``
    identical solves."""
    from hovi import trajopt
    from hovi.examples import swingups
    method = trajopt.VI(s=s) if kind == "vi" else trajopt.HermiteSimpson("implicit")
    best = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        prob = swingups.EXAMPLES[name](N=N)
        r = trajopt.solve(prob, method, verbose=False, guess=GUESSES[name], hessian=hessian, continuation=continuation)
        total = time.perf_counter() - t0
        if best is None or total < best[1]:
            best = (r, total)
    r, total = best
    options = ([] if hessian == "auto" else [f"{hessian} Hessian"]) + ([] if continuation is True or s == 1 else
                                                                      ["direct"] if not continuation else
                                                                      [f"{continuation} first stage"])
    return {"solver": f"hovi {label}" + (f" ({', '.join(options)})" if options else ""), "N": N,
            "success": bool(r.success), "continuation": r.solver.get("continuation", {}).get("used", False),
            "status": r.status, "iterations": r.iterations, "cost": r.cost, "timing": dict(r.timing),
            "cost_error": abs(r.cost - ref_cost) / abs(ref_cost), "setup_seconds": total - r.wall_seconds,
            "ipopt_seconds": r.wall_seconds, "solve_seconds": total,
            "one_interval_error": hovi_one_interval_error(r, name) if r.success else float("nan")}


def warm_up(with_hovi=True):
    """One small solve on each side first: loading CasADi's IPOPT plugin and its libraries (~0.3 s)
    and hovi's first transcription are one-off costs of a process, not of a solve."""
    for graph in CASADI_GRAPHS:
        solve("pendulum", 4, graph=graph)
    if with_hovi:
        from hovi import trajopt
        from hovi.examples import swingups
        for method in (trajopt.VI(s=2), trajopt.HermiteSimpson("implicit")):
            trajopt.solve(swingups.pendulum_swingup(N=4), method, verbose=False)


CASADI_GRAPHS = ("sx", "mx")


def timed_solve(name, N, graph, repeat=1) -> Solution:
    """The fastest (set-up + IPOPT) of ``repeat`` identical CasADi solves."""
    return min((solve(name, N, graph=graph) for _ in range(repeat)), key=lambda s: s.setup_seconds + s.ipopt_seconds)


# hovi's rows also at coarser N: the cheapest configuration reaching CasADi's accuracy may need fewer stages
HOVI_GRIDS = {"pendulum": (10, 20, 40, 80), "cartpole": (20, 40, 50, 80), "acrobot": (40, 60, 80, 160)}


def run(grids=GRIDS, with_hovi=True, refine=16, hessians=("auto",), repeat=1, log=print, references=None):
    """Every swing-up at each of its N: CasADi HS (SX and MX graphs), then (with_hovi) hovi's VI s = 1,
    2, 3 and HS with each Hessian in ``hessians``, in this process; the reference from CasADi HS at
    refine x the largest N. Times: the fastest of ``repeat`` identical solves."""
    out = {"repeat": repeat, "ipopt": ipopt_versions(), "ipopt_options_casadi": IPOPT_OPTIONS, "guesses": GUESSES, "swingups": {}}
    warm_up(with_hovi)
    for name, Ns in grids.items():
        sols = {(N, g): timed_solve(name, N, g, repeat) for N in Ns for g in CASADI_GRAPHS}
        ref = references[name] if references and name in references else \
            reference(name, refine * max(Ns), sols[max(Ns), "sx"])
        log(f"{name}: reference cost {ref['cost']:.10g} (HS N = {ref['N']}; VI s=3 N = {ref['vi3_N']}: "
            f"{ref['vi3_cost']:.10g})")
        rows = []
        for N in Ns:
            rows += [casadi_row(sols[N, g], ref["cost"], g) for g in CASADI_GRAPHS]
        for N in sorted(set(Ns) | set(HOVI_GRIDS.get(name, ()) if max(Ns) == max(GRIDS[name]) else ())):
            if with_hovi:
                for hess in hessians:
                    for label, kind, s in HOVI_METHODS:
                        stages = (True, False, "lbfgs") if name == "acrobot" else (True, False)
                        for continuation in (stages if s > 1 or kind == "hs" else (True,)):
                            if hess == "lbfgs" and not continuation:
                                continue
                            rows.append(hovi_row(name, N, label, kind, s, ref["cost"], hess, repeat, continuation))
        for r in rows:
            log(f"  N={r['N']:4d} {r['solver']:24s} {'ok ' if r['success'] else 'FAIL'} set-up {1e3 * r['setup_seconds']:8.1f} ms"
                f"  IPOPT {1e3 * r['ipopt_seconds']:8.1f} ms  {r['iterations']:4d} it  cost {r['cost']:.8g}"
                f"  cost err {r['cost_error']:.1e}  1-interval err {r['one_interval_error']:.1e}")
        out["swingups"][name] = {"grid": list(Ns), "reference": ref, "rows": rows}
    if with_hovi:
        out["matches"] = cheapest_matches(out)
    return out


def cheapest_matches(out) -> dict:
    """Per swing-up: the CasADi baseline at its largest N (the faster of its SX and MX graphs, by set-up +
    IPOPT), and the cheapest hovi row (any N, Hessian) reaching its accuracy (cost error and
    one-interval error each no larger than the baseline's), with the ratio of solve times (hovi /
    CasADi; None when no hovi row reaches it)."""
    res = {}
    for name, d in out["swingups"].items():
        Nmax = max(d["grid"])
        base = min((r for r in d["rows"] if r["solver"].startswith("CasADi") and r["N"] == Nmax and r["success"]),
                   key=lambda r: r["solve_seconds"], default=None)
        if base is None:
            res[name] = None
            continue
        ok = [r for r in d["rows"] if r["solver"].startswith("hovi") and r["success"]
              and r["cost_error"] <= base["cost_error"] and r["one_interval_error"] <= base["one_interval_error"]]
        best = min(ok, key=lambda r: r["solve_seconds"], default=None)
        res[name] = {"casadi": {k: base[k] for k in ("solver", "N", "solve_seconds", "cost_error", "one_interval_error")},
                     "hovi": None if best is None else {k: best[k] for k in ("solver", "N", "solve_seconds", "cost_error",
                                                                                "one_interval_error")},
                     "time_ratio": None if best is None else best["solve_seconds"] / base["solve_seconds"]}
    return res


def report(out) -> str:
    lines = ["| swing-up | N | solver | set-up [ms] | IPOPT [ms] | iterations | cost | cost error | one-interval error |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, d in out["swingups"].items():
        for r in d["rows"]:
            ok = "" if r["success"] else " (failed)"
            lines.append(f"| {name} | {r['N']} | {r['solver']}{ok} | {1e3 * r['setup_seconds']:.1f} | "
                         f"{1e3 * r['ipopt_seconds']:.1f} | {r['iterations']} | {r['cost']:.8g} | {r['cost_error']:.1e} | "
                         f"{r['one_interval_error']:.1e} |")
    lines += ["", "| swing-up | CasADi baseline (largest N) | solve [ms] | cheapest hovi at its accuracy | solve [ms] | hovi / CasADi |",
              "|---|---|---|---|---|---|"]
    for name, m in out.get("matches", {}).items():
        if m is None:
            lines.append(f"| {name} | (CasADi failed) | | | | |")
            continue
        c, h = m["casadi"], m["hovi"]
        lines.append(f"| {name} | {c['solver']} N = {c['N']} | {1e3 * c['solve_seconds']:.1f} | " +
                     ("none of the rows | | |" if h is None else
                      f"{h['solver']} N = {h['N']} | {1e3 * h['solve_seconds']:.1f} | {m['time_ratio']:.2f} |"))
    return "\n".join(lines)


def main():
    ap = study_parser(__doc__, "the pendulum at N = 20 only")
    ap.add_argument("--no-hovi", action="store_true", help="CasADi's solves only")
    ap.add_argument("--lbfgs", action="store_true", help="hovi also with hessian='lbfgs' (the default is hovi's: 'auto')")
    ap.add_argument("--reuse-references", action="store_true",
                    help="take the reference optima from the last bench/results/casadi_baseline.json")
    ap.add_argument("--repeat", type=int, default=3, help="time the fastest of this many identical solves")
    ap.add_argument("--only", nargs="+", choices=sorted(GRIDS), help="run these swing-ups and keep the others' rows "
                    "from the last bench/results/casadi_baseline.json (implies --reuse-references)")
    args = ap.parse_args()
    _require_casadi()
    from common import write_json
    grids = {"pendulum": (20,)} if args.quick else {name: GRIDS[name] for name in (args.only or GRIDS)}
    references = last = None
    if (args.reuse_references or args.only) and not args.quick:
        import json
        from common import COMMITTED
        with open(os.path.join(COMMITTED, "casadi_baseline.json")) as f:
            last = json.load(f)
        references = {name: d["reference"] for name, d in last["swingups"].items()}
    out = run(grids, with_hovi=not args.no_hovi, refine=8 if args.quick else 16,
              hessians=("auto", "lbfgs") if args.lbfgs else ("auto",), repeat=1 if args.quick else args.repeat,
              references=references)
    if args.only and not args.quick:   # the other swing-ups' rows as the last run left them (its 'kept' list)
        kept = [name for name in last["swingups"] if name not in grids]
        out["swingups"] = {name: out["swingups"].get(name) or last["swingups"][name] for name in GRIDS}
        out["kept_from_last_run"] = kept
        if not args.no_hovi:
            out["matches"] = cheapest_matches(out)
    path = write_json("casadi_baseline_quick.json" if args.quick else "casadi_baseline.json", out)
    print(report(out))
    print("wrote", path)


if __name__ == "__main__":
    main()
