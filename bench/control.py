"""Control on the VI: box-FDDP on the VI against Crocoddyl's box-FDDP (RK4), TVLQR
Monte-Carlo on the swing-ups, the LQR's region of attraction at the upright, MPC's solve rate, and
FDDP through contact.

A. FDDP: hovi.trajopt.FDDP on VI(s), s = 1, 2, 3, against Crocoddyl 3.2.1's SolverBoxFDDP on RK4
   (bench/crocoddyl_baseline.py) on the same three swing-ups (pendulum, cart-pole, acrobot; held
   controls, |u| <= u_max, cost sum dt R u^2 + Wq |q_N - q_T|^2 + Wv |v(T)|^2, R = 1, Wq = 1000,
   Wv = 100), from zero controls, on one core, for N = the baseline's N times 1, 2, 4, ... Per solve:
   the solver's own time (hovi: the C++ solve, result.timing["solver"]; Crocoddyl: solver.solve),
   best of up to 5 in the same process with the solvers alternating, iterations, cost, and the
   accuracy of the optimised motion: its held controls re-simulated exactly (DOP853, rtol = atol =
   1e-12, crocoddyl_baseline.resimulate) against the solver's own knots (hovi: q and M(q)^-1 p),
   max over the knots of the inf-norm (``resim``), and the same one stage at a time from each knot
   (``step``: the transcription's local error, without the chaotic growth of the acrobot's
   open-loop errors). From the sweep: for each solver the time to reach a re-simulation error
   (the cheapest N whose error is at or below the level).
   Stopping tests: hovi sum_k |Q_u|^2 < 1e-9 (FDDP's default); Crocoddyl |expected improvement|
   < 1e-10 (the baseline's); both at most 2000 iterations.
B. TVLQR Monte-Carlo: the cart-pole and acrobot swing-ups optimised by FDDP on VI(2) at dt = 0.02,
   hovi.control.tvlqr along them (final weight: the upright LQR's cost-to-go), then the LQR at the
   upright for 1 s (one Policy: its stages are the TVLQR's and, after the motion, the LQR's). 100
   perturbed runs per condition with simulate_batch: initial-state noise, mass error (each body's
   mass and inertia x U[0.8, 1.2], model.copy().scale_mass), a push at mid-motion on the pole /
   link2 tip, all three; open loop (the same Policy with zero gains) against closed loop.
C. LQR at the upright: region of attraction under the swing-ups' control limits (grids of initial
   offsets, 5 s at 100 Hz).
D. MPC (hovi.control.MPC, FDDP on VI(s), period 1) holding the cart-pole upright at 100 Hz under
   pushes: solve time per control period, real-time factor, iterations; one IPOPT solve and one
   cold FDDP solve of the same horizon problem for the ratio.
E. FDDP through contact: LittleDog standing -> 3 cm crouch, held or smoothed Jacobians (smoothing).

    python bench/control.py [--quick] [--only A B C D E] [--tables]

Writes bench/results/control.json (control_quick.json), control_roa.png and the tables in
bench/README.md (section "Control"; not for --quick). A full run of some parts (--only) keeps the
other parts from the last control.json; --tables rebuilds the README tables from it.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

import hovi
from hovi import _core, control, trajopt
from hovi.control import Policy

import crocoddyl_baseline as cb
from common import COMMITTED, RESULTS, hovi_commit, json_ready, markdown_table, update_readme_section, write_json

LEVELS = (1e-3, 1e-5)             # re-simulation errors for "time at equal accuracy"
HOVI_TOL, CROC_TH_STOP, MAX_ITER = 1e-9, 1e-10, 2000
SUCCESS = dict(angle=0.1, velocity=0.5)  # rad, and rad/s or m/s (inf-norm), at the end


# ----------------------------------------------------------------------------------------------
# A. FDDP against Crocoddyl
# ----------------------------------------------------------------------------------------------

def swingup_problem(name: str, N: int, *, T: float | None = None) -> trajopt.Problem:
    """crocoddyl_baseline's swing-up `name` as a hovi Problem: held controls, the same bounds, cost
    ControlEffort(R) (sum dt R u_k^2) + TerminalCost(q_T, Wq, velocity_weight=Wv)."""
    spec = cb.SWINGUPS[name]
    model = cb.hovi_model(name)
    pr = trajopt.Problem(model, N, spec["T"] if T is None else T, controls="held",
                         u_bounds=(-spec["u_max"], spec["u_max"]), q_bounds=(-np.inf, np.inf))
    pr.initial_state(np.zeros(model.n))
    pr.add_cost(trajopt.ControlEffort(1.0))
    pr.add_cost(trajopt.TerminalCost(spec["q_T"], 1000.0, velocity_weight=100.0))
    return pr


def step_error(name: str, xs, us, dt: float) -> float:
    """max over stages of |x_{k+1} - exact(x_k, u_k)|_inf: each stage re-simulated from the solver's
    own knot (DOP853, 1e-12)."""
    from scipy.integrate import solve_ivp
    f = cb._ABA(name)
    worst = 0.0
    for k, u in enumerate(np.asarray(us).reshape(len(us), -1)):
        tau = f.B @ u
        sol = solve_ivp(lambda t, x: f.xdot(x, tau), (0.0, dt), xs[k], method="DOP853", rtol=1e-12, atol=1e-12)
        worst = max(worst, float(np.abs(sol.y[:, -1] - xs[k + 1]).max()))
    return worst


class HoviSide:
    label = "hovi"

    def __init__(self, name, N, s, tol=HOVI_TOL):
        self.name, self.N, self.s, self.tol = name, N, s, tol
        self.label = f"hovi VI s={s}"
        self.problem = swingup_problem(name, N)

    def solve(self):
        r = trajopt.FDDP(tol=self.tol, max_iterations=MAX_ITER).solve(self.problem, trajopt.VI(self.s))
        self.last = r
        return float(r.timing["solver"])

    def summary(self):
        r, n = self.last, self.problem.model.n
        xs = cb.hovi_state_to_x(self.name, r.solver["xs"][:, :n], r.solver["xs"][:, n:])
        return dict(iterations=int(r.iterations), cost=float(r.cost), converged=bool(r.success),
                    stop=float(r.solver["stop"]), xs=xs, us=np.asarray(r.solver["us"]))


class CrocSide:
    """Crocoddyl's SolverBoxFDDP as crocoddyl_baseline.solve_swingup runs it, the problem built once
    and each solve by a fresh solver from the same initial guess (us = 0, xs = its rollout)."""

    def __init__(self, name, N, th_stop=CROC_TH_STOP):
        import crocoddyl
        self.crocoddyl, self.name, self.N, self.th_stop = crocoddyl, name, N, th_stop
        self.label = "Crocoddyl RK4"
        self.problem, self.info = cb.build_problem(name, N, nthreads=1)
        self.us0 = [np.zeros(self.info["nu"])] * self.info["N"]
        self.xs0 = self.problem.rollout(self.us0)

    def solve(self):
        solver = self.crocoddyl.SolverBoxFDDP(self.problem)
        solver.th_stop = self.th_stop
        t = time.perf_counter()
        converged = solver.solve(self.xs0, self.us0, MAX_ITER, True)
        seconds = time.perf_counter() - t
        self.last, self.converged = solver, bool(converged)
        return seconds

    def summary(self):
        s = self.last
        us = np.array(s.us)
        if self.info["nu"] != self.info["B"].shape[1]:
            us = us[:, :1]  # the cart-pole's pinned hinge torque dropped
        return dict(iterations=int(s.iter) + int(self.converged), cost=float(s.cost), converged=self.converged,
                    stop=float(s.stop), xs=np.array(s.xs), us=us)


def measure_sides(sides, repeats, long_solve=5.0):
    """Best-of-`repeats` times of the sides, alternating (one solve of each per round); a side whose
    first solve took more than `long_solve` s is solved 2 times at most, 1 above 4 long_solve."""
    times = [[] for _ in sides]
    for r in range(repeats):
        for i, side in enumerate(sides):
            if r and (times[i][0] > 4 * long_solve or (r >= 2 and times[i][0] > long_solve)):
                continue
            times[i].append(side.solve())
    return times


def fddp_rows(name, mults, repeats, ss=(1, 2, 3)):
    spec = cb.SWINGUPS[name]
    rows = []
    for mult in mults:
        N = spec["N"] * mult
        sides = [HoviSide(name, N, s) for s in ss] + [CrocSide(name, N)]
        times = measure_sides(sides, repeats)
        dt = spec["T"] / N
        for side, ts in zip(sides, times):
            out = side.summary()
            xs, us = out.pop("xs"), out.pop("us")
            resim = cb.resimulate(name, xs[0], us, dt)
            err = np.abs(resim - xs).max(axis=1)
            n = xs.shape[1] // 2
            row = dict(swingup=name, solver=side.label, N=N, dt=dt, seconds=min(ts), seconds_all=ts, **out,
                       resim_error=float(err.max()), resim_final_error=float(err[-1]),
                       step_error=step_error(name, xs, us, dt),
                       q_miss=float(np.abs(xs[-1, :n] - np.asarray(spec["q_T"])).max()),
                       cost_formula=cb.cost_formula(xs, us, dt, np.asarray(spec["q_T"])))
            rows.append(row)
            print(f"  {name:8} N={N:4d} {side.label:14} {row['seconds']:8.4f} s  it {row['iterations']:4d}  "
                  f"cost {row['cost']:9.5f}  resim {row['resim_error']:8.2e}  step {row['step_error']:8.2e}"
                  f"{'' if row['converged'] else '  NOT CONVERGED'}", flush=True)
    # a row on another local optimum: cost 5 % above the best cost of that swing-up at that N
    for row in rows:
        best = min(r["cost"] for r in rows if r["N"] == row["N"])
        row["other_optimum"] = bool(row["cost"] > 1.05 * best)
    return rows


def time_to_reach(rows, solver, level):
    """The cheapest converged solve of `solver` whose re-simulation error is <= level (None if none)."""
    ok = [r for r in rows if r["solver"] == solver and r["converged"] and r["resim_error"] <= level]
    if not ok:
        return None
    r = min(ok, key=lambda r: r["seconds"])
    return dict(N=r["N"], seconds=r["seconds"], resim_error=r["resim_error"], cost=r["cost"], other_optimum=r["other_optimum"])


def tight_costs(name, repeats=3):
    """Each solver at its nominal N with a tight stopping test: how far the default test stops from
    its optimum (cost relative difference); and hovi with the tolerance (1e-9, 1e-10, ...) at which
    its gap is no larger than Crocoddyl's, with its time (best of `repeats`): the time at equal
    convergence precision."""
    N = cb.SWINGUPS[name]["N"]
    out = {}
    for side, tight in [(CrocSide(name, N), CrocSide(name, N, th_stop=1e-20))] + \
                       [(HoviSide(name, N, s), HoviSide(name, N, s, tol=1e-20)) for s in (1, 2, 3)]:
        side.solve()
        tight.solve()
        a, b = side.summary(), tight.summary()
        gap = (a["cost"] - b["cost"]) / abs(b["cost"])
        out[side.label] = dict(cost=a["cost"], tight_cost=b["cost"], tight_iterations=b["iterations"], relative_gap=gap)
        if isinstance(side, HoviSide):
            target = out["Crocoddyl RK4"]["relative_gap"]
            for tol in (1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14):
                h = HoviSide(name, N, side.s, tol=tol)
                seconds = min(h.solve() for _ in range(repeats))
                m = h.summary()
                matched = (m["cost"] - b["cost"]) / abs(b["cost"])
                if matched <= target or tol == 1e-14:
                    break
            out[side.label].update(matched_tol=tol, matched_gap=matched, matched_iterations=m["iterations"],
                                   matched_seconds=seconds)
    return out


def part_a(quick, repeats):
    mults = {"pendulum": (1, 2), "cartpole": (1,), "acrobot": (1,)} if quick else \
        {"pendulum": (1, 2, 4, 8, 16), "cartpole": (1, 2, 4, 8, 16), "acrobot": (1, 2, 4, 8, 16, 32)}
    out = {"stopping": {"hovi": f"sum_k |Q_u|^2 < {HOVI_TOL:g}", "crocoddyl": f"|expected improvement| < {CROC_TH_STOP:g}",
                        "max_iterations": MAX_ITER},
           "levels": list(LEVELS), "swingups": {}}
    for name in cb.SWINGUPS:
        rows = fddp_rows(name, mults[name], repeats)
        solvers = sorted({r["solver"] for r in rows})
        reach = {str(level): {s: time_to_reach(rows, s, level) for s in solvers} for level in LEVELS}
        entry = {"spec": {k: (list(v) if isinstance(v, list) else v) for k, v in cb.SWINGUPS[name].items()},
                 "rows": rows, "time_to_reach": reach}
        if not quick:
            entry["tight_stopping"] = tight_costs(name)
        out["swingups"][name] = entry
    return out


# ----------------------------------------------------------------------------------------------
# B. TVLQR Monte-Carlo
# ----------------------------------------------------------------------------------------------

MC = {
    # plant and controller step, LQR/TVLQR weights on (q, q̇) and u, push body, point (the tip) and size
    "cartpole": dict(dt=0.02, s=2, weights=dict(q_weight=[100.0, 1000.0], v_weight=[1.0, 10.0], u_weight=1e-3),
                     push_body="pole", push_point=[0.0, 0.0, -0.5], push=0.3, angles=[1]),
    "acrobot": dict(dt=0.02, s=2, weights=dict(q_weight=[100.0, 100.0], v_weight=[1.0, 1.0], u_weight=1e-3),
                    push_body="link2", push_point=[0.0, 0.0, -1.0], push=1.0, angles=[0, 1]),
}
NOISE_Q, NOISE_V, MASS_RANGE = 0.05, 0.1, (0.8, 1.2)


def upright_lqr(name, integ):
    spec, mc = cb.SWINGUPS[name], MC[name]
    return control.lqr(integ, np.asarray(spec["q_T"]), u_limits=(-spec["u_max"], spec["u_max"]), **mc["weights"])


def concatenate(a: Policy, b: Policy) -> Policy:
    """One Policy: a's stages, then b's (the last stage holds after)."""
    return Policy(x_ref=np.vstack([a.x_ref, b.x_ref]), u_ref=np.concatenate([a.u_ref, b.u_ref]),
                  gains=np.concatenate([a.gains, b.gains]), lower=a.lower, upper=a.upper,
                  cost_to_go=np.concatenate([a.cost_to_go, b.cost_to_go]), dt=a.dt, s=a.s)


def final_errors(name, plants, runs):
    """Per run: the largest wrapped angle error to the upright and |q̇|_inf at the last knot, the
    cart's |x| (cart-pole), and whether every step converged."""
    qT = np.asarray(cb.SWINGUPS[name]["q_T"])
    ang = MC.get(name, {"angles": [1] if name == "cartpole" else [0, 1]})["angles"]
    q = np.array([r.trajectory.q[-1] for r in runs])
    p = np.array([r.trajectory.p[-1] for r in runs])
    v = np.array([pl.velocity(qq, pp) if np.all(np.isfinite(pp)) else np.full(len(qq), np.inf)
                  for pl, qq, pp in zip(plants if len(plants) == len(runs) else plants * len(runs), q, p)])
    d = q - qT
    d[:, ang] = (d[:, ang] + np.pi) % (2 * np.pi) - np.pi
    conv = np.array([r.converged for r in runs])
    angle = np.where(conv, np.abs(d[:, ang]).max(axis=1), np.inf)
    vel = np.where(conv, np.abs(v).max(axis=1), np.inf)
    ok = conv & (angle < SUCCESS["angle"]) & (vel < SUCCESS["velocity"])
    return ok, angle, vel, conv, np.abs(d[:, 0])


def part_b(quick):
    runs = 10 if quick else 100
    out = {"runs": runs, "success": f"at the end (1 s after the motion): every angle within {SUCCESS['angle']} rad of the "
           f"upright (wrapped), |q̇|_inf < {SUCCESS['velocity']} (rad/s, m/s), every plant step converged; the cart's "
           "position not required", "noise": f"q0 + U[-{NOISE_Q}, {NOISE_Q}] (rad, m), q̇0 = U[-{NOISE_V}, {NOISE_V}]",
           "mass": f"each body's mass and rotational inertia x U{list(MASS_RANGE)} (mass_10pct: the same draws halved, "
           "x U[0.9, 1.1])", "robots": {}}
    for name in ("cartpole", "acrobot"):
        spec, mc = cb.SWINGUPS[name], MC[name]
        dt, s = mc["dt"], mc["s"]
        N = int(round(spec["T"] / dt))
        pr = swingup_problem(name, N)
        t0 = time.perf_counter()
        res = trajopt.FDDP(tol=HOVI_TOL, max_iterations=MAX_ITER).solve(pr, trajopt.VI(s))
        opt_seconds = time.perf_counter() - t0
        integ = hovi.Integrator(pr.model, s=s, dt=dt)
        qT = np.asarray(spec["q_T"])
        lim = (-spec["u_max"], spec["u_max"])
        L = upright_lqr(name, integ)
        # the LQR's cost-to-go (on (q, p)) as TVLQR's final weight on (q, q̇): W = T^-T P T^-1
        Tm = _core.control.velocity_state_map(pr.model, qT[None], np.zeros((1, pr.model.n)))[0]
        Ti = np.linalg.inv(Tm)
        WN = Ti.T @ L.cost_to_go[0] @ Ti
        tv = control.tvlqr(integ, res, u_limits=lim, final_weight=0.5 * (WN + WN.T), **mc["weights"])
        closed = concatenate(tv, L)
        open_ = Policy(x_ref=closed.x_ref, u_ref=closed.u_ref, gains=np.zeros_like(closed.gains), lower=closed.lower,
                       upper=closed.upper, cost_to_go=closed.cost_to_go, dt=dt, s=s)
        K = tv.stages
        steps = K + int(round(1.0 / dt))
        rng = np.random.default_rng(32)
        q0 = rng.uniform(-NOISE_Q, NOISE_Q, (runs, pr.model.n))
        v0 = rng.uniform(-NOISE_V, NOISE_V, (runs, pr.model.n))
        factors = rng.uniform(*MASS_RANGE, (runs, pr.model.n))
        signs = rng.choice([-1.0, 1.0], runs)
        entry = {"N": N, "dt": dt, "s": s, "swingup_cost": float(res.cost), "swingup_iterations": int(res.iterations),
                 "swingup_seconds": opt_seconds, "plan_end_miss": float(np.abs(res.solver["xs"][-1][:pr.model.n] - qT).max()),
                 "weights": mc["weights"], "lqr_gain": L.gains[0].tolist(), "push": {
                     "body": mc["push_body"], "point": mc["push_point"], "impulse_Ns": mc["push"], "time": spec["T"] / 2,
                     "direction": "world x, sign random"}, "hold_seconds": 1.0, "conditions": {}}
        for cond in ("none", "noise", "mass", "push", "all", "mass_10pct"):
            plants = []
            for b in range(runs):
                model = pr.model.copy()
                if cond in ("mass", "all", "mass_10pct"):
                    for j, body in enumerate(pr.model.body_names):
                        f = float(factors[b, j])
                        model.scale_mass(body, 1 + (f - 1) / 2 if cond == "mass_10pct" else f)
                plants.append(hovi.Integrator(model, s=s, dt=dt))
            pushes = [[control.Push(spec["T"] / 2, mc["push_body"], [signs[b] * mc["push"], 0.0, 0.0],
                                    point=mc["push_point"])] if cond in ("push", "all") else [] for b in range(runs)]
            noisy = cond in ("noise", "all")
            row = {}
            for label, pol in (("open_loop", open_), ("closed_loop", closed)):
                t0 = time.perf_counter()
                rr = control.simulate_batch(plants, pol, q0 if noisy else np.zeros(pr.model.n), steps,
                                            qdot0=v0 if noisy else np.zeros(pr.model.n), pushes=pushes, runs=runs,
                                            threads=1)
                wall = time.perf_counter() - t0
                ok, angle, vel, conv, cart = final_errors(name, plants, rr)
                qK = np.array([r.trajectory.q[min(K, r.trajectory.steps)] for r in rr]) - qT
                qK[:, mc["angles"]] = (qK[:, mc["angles"]] + np.pi) % (2 * np.pi) - np.pi
                at_T = np.abs(qK[:, mc["angles"]]).max(axis=1) < SUCCESS["angle"]
                row[label] = dict(success_rate=float(ok.mean()), converged_rate=float(conv.mean()),
                                  upright_at_end_of_motion_rate=float(np.mean(at_T & conv)),
                                  median_angle_error=float(np.median(angle)), median_velocity=float(np.median(vel)),
                                  max_cart_offset_of_successes=float(cart[ok].max()) if name == "cartpole" and ok.any() else None,
                                  saturated_fraction=float(np.mean([np.mean(np.abs(r.u) >= spec["u_max"] - 1e-9) for r in rr])),
                                  wall_seconds=wall)
            entry["conditions"][cond] = row
            print(f"  {name:8} {cond:6} open {row['open_loop']['success_rate']:5.2f}  closed "
                  f"{row['closed_loop']['success_rate']:5.2f}", flush=True)
        out["robots"][name] = entry
    return out


# ----------------------------------------------------------------------------------------------
# C. LQR region of attraction
# ----------------------------------------------------------------------------------------------

def roa_map(name, integ, policy, grid_a, grid_b, axes, seconds=5.0):
    """Success (C's criterion) on a grid of initial offsets from the upright: axes = (what a is,
    what b is), each 'q<i>' (an angle offset) or 'v<i>' (an angular velocity)."""
    qT = np.asarray(cb.SWINGUPS[name]["q_T"])
    n = integ.n
    A, Bv = np.meshgrid(grid_a, grid_b, indexing="ij")
    Q = np.tile(qT, (A.size, 1))
    V = np.zeros((A.size, n))
    for ax, vals in zip(axes, (A.ravel(), Bv.ravel())):
        (Q if ax[0] == "q" else V)[:, int(ax[1:])] += vals
    steps = int(round(seconds / integ.dt))
    runs = control.simulate_batch(integ, policy, Q, steps, qdot0=V, runs=A.size, threads=1)
    ok, *_ = final_errors(name, [integ], runs)
    return ok.reshape(A.shape)


def largest_offset(grid, ok_line):
    """The largest a such that every grid point with |offset| <= a recovers (0 if the origin fails)."""
    order = np.argsort(np.abs(grid), kind="stable")
    best = 0.0
    for i in order:
        if not ok_line[i]:
            break
        best = abs(grid[i])
    return float(best)


def part_c(quick):
    dt, s = 0.01, 2
    out = {"dt": dt, "s": s, "seconds": 5.0, "success": "as B, at the end of 5 s", "maps": {}}
    grid = lambda half, count: np.linspace(-half, half, count)  # noqa: E731  (odd counts: 0 on the grid)
    specs = [("cartpole", ("q1", "v1"), grid(1.5, 11 if quick else 121), grid(6.0, 5 if quick else 49)),
             ("acrobot", ("q0", "v0"), grid(0.1, 11 if quick else 41), grid(0.5, 5 if quick else 41)),
             ("acrobot", ("q0", "q1"), grid(0.1, 11 if quick else 41), grid(0.3, 5 if quick else 41))]
    for name, axes, ga, gb in specs:
        spec = cb.SWINGUPS[name]
        integ = hovi.Integrator(cb.hovi_model(name), s=s, dt=dt)
        L = upright_lqr(name, integ)
        t0 = time.perf_counter()
        ok = roa_map(name, integ, L, ga, gb, axes)
        zero_b = int(np.argmin(np.abs(gb)))
        zero_a = int(np.argmin(np.abs(ga)))
        # the same line (other = 0) without control limits: is it the limit or the nonlinearity?
        free = roa_map(name, integ, L.with_limits(-np.inf, np.inf), ga, gb[zero_b:zero_b + 1], axes)[:, 0]
        key = f"{name}_{axes[0]}_{axes[1]}"
        out["maps"][key] = dict(robot=name, axes=list(axes), u_limits=[-spec["u_max"], spec["u_max"]], weights=MC[name]["weights"],
                                grid_a=ga.tolist(), grid_b=gb.tolist(), success=ok.astype(int).tolist(),
                                fraction=float(ok.mean()), largest_a_at_b0=largest_offset(ga, ok[:, zero_b]),
                                largest_a_at_b0_without_limits=largest_offset(ga, free),
                                largest_b_at_a0=largest_offset(gb, ok[zero_a, :]),
                                largest_recovering_a=float(np.abs(ga[ok.any(axis=1)]).max()) if ok.any() else 0.0,
                                wall_seconds=time.perf_counter() - t0)
        m = out["maps"][key]
        print(f"  {key:20} recovers from |{axes[0]}| <= {m['largest_a_at_b0']:.3f} ({axes[1]} = 0), "
              f"|{axes[1]}| <= {m['largest_b_at_a0']:.3f} ({axes[0]} = 0); {100 * m['fraction']:.0f} % of the grid", flush=True)
    return out


AXIS_NAMES = {("cartpole", "q1"): "pole angle offset (rad)", ("cartpole", "v1"): "pole angular velocity (rad/s)",
              ("acrobot", "q0"): "shoulder offset (rad)", ("acrobot", "v0"): "shoulder velocity (rad/s)",
              ("acrobot", "q1"): "elbow offset (rad)"}


def plot_roa(c, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    maps = list(c["maps"].values())
    fig, axs = plt.subplots(1, len(maps), figsize=(4.2 * len(maps), 3.6))
    for ax, m in zip(np.atleast_1d(axs), maps):
        ga, gb, ok = np.array(m["grid_a"]), np.array(m["grid_b"]), np.array(m["success"])
        ax.pcolormesh(ga, gb, ok.T, cmap="Greens", vmin=-0.2, vmax=1.2, shading="nearest")
        ax.set_xlabel(AXIS_NAMES[(m["robot"], m["axes"][0])])
        ax.set_ylabel(AXIS_NAMES[(m["robot"], m["axes"][1])])
        ax.set_title(f"{m['robot']} LQR, |u| <= {m['u_limits'][1]:g}: {100 * m['fraction']:.0f} % recover", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# D. MPC rate
# ----------------------------------------------------------------------------------------------

def mpc_problem(H, dt, q0):
    pr = trajopt.Problem(cb.hovi_model("cartpole"), H, H * dt, controls="held", u_bounds=(-20, 20),
                         q_bounds=(-np.inf, np.inf))
    pr.initial_state(list(q0))
    pr.add_cost(trajopt.ControlEffort(0.01))
    pr.add_cost(trajopt.StateTracking([0, np.pi], [1.0, 10.0], velocity_weight=[0.1, 0.1]))
    pr.add_cost(trajopt.TerminalCost([0, np.pi], [10.0, 100.0], velocity_weight=[1.0, 1.0]))
    return pr


def part_d(quick):
    dt, seconds = 0.01, (2.0 if quick else 6.0)
    q0 = [0.1, np.pi - 0.3]
    pushes = [control.Push(1.0, "pole", [0.3, 0.0, 0.0], point=[0.0, 0.0, -0.5])] if quick else \
        [control.Push(2.0, "pole", [0.3, 0.0, 0.0], point=[0.0, 0.0, -0.5]),
         control.Push(3.5, "pole", [-0.3, 0.0, 0.0], point=[0.0, 0.0, -0.5])]
    configs = [(30, 1, 10)] if quick else [(H, s, it) for H in (30, 50) for s in (1, 2) for it in (3, 10)]
    out = {"dt": dt, "rate_hz": 1 / dt, "seconds": seconds, "q0": q0, "plant": "hovi.Integrator(cartpole, s=3, dt=0.01)",
           "problem": "ControlEffort(0.01) + StateTracking([0, pi], [1, 10], velocity_weight 0.1) + "
                      "TerminalCost([0, pi], [10, 100], velocity_weight 1), |u| <= 20, period 1",
           "pushes": [dict(time=p.time, impulse_Ns=p.impulse[0], point="pole tip") for p in pushes], "runs": [], "ipopt": []}
    steps = int(round(seconds / dt))
    for H, s, it in configs:
        mpc = control.MPC(mpc_problem(H, dt, q0), s=s, period=1, max_iterations=it)
        plant = hovi.Integrator(cb.hovi_model("cartpole"), s=3, dt=dt)
        t0 = time.perf_counter()
        run = mpc.run(plant, q0, steps, pushes=pushes)
        wall = time.perf_counter() - t0
        ss = run.solve_seconds
        th = run.trajectory.q[:, 1] - np.pi
        first_push = int(round(pushes[0].time / dt))
        row = dict(horizon=H, horizon_seconds=H * dt, s=s, max_iterations=it, solves=len(ss),
                   mean_ms=1e3 * float(ss.mean()), p95_ms=1e3 * float(np.percentile(ss, 95)), worst_ms=1e3 * float(ss.max()),
                   worst_after_first_ms=1e3 * float(ss[1:].max()), over_period=int(np.sum(ss > dt)),
                   real_time_factor=run.real_time_factor, mean_iterations=float(run.iterations.mean()),
                   converged_fraction=float(run.converged.mean()), plant_converged=bool(run.trajectory.converged),
                   max_pole_error_after_push=float(np.abs(th[first_push:]).max()),
                   max_pole_error_before_push=float(np.abs(th[int(round(1.0 / dt)) // 2:first_push]).max()),
                   final_pole_error=float(abs(th[-1])), final_cart=float(run.trajectory.q[-1, 0]),
                   max_cart=float(np.abs(run.trajectory.q[:, 0]).max()),
                   wall_seconds=wall)
        row["holds"] = bool(row["plant_converged"] and row["final_pole_error"] < 0.05 and row["max_pole_error_after_push"] < np.pi / 2)
        out["runs"].append(row)
        print(f"  MPC H={H} s={s} it<={it}: mean {row['mean_ms']:.2f} ms p95 {row['p95_ms']:.2f} worst {row['worst_ms']:.2f} "
              f"rtf {row['real_time_factor']:.1f} it {row['mean_iterations']:.2f} pole max {row['max_pole_error_after_push']:.3f} "
              f"end {row['final_pole_error']:.4f}", flush=True)
    for H, s in sorted({(c[0], c[1]) for c in configs}):
        times, fddp_times = [], []
        for _ in range(1 if quick else 3):
            t0 = time.perf_counter()
            ri = trajopt.solve(mpc_problem(H, dt, q0), trajopt.VI(s), verbose=False)
            times.append(time.perf_counter() - t0)
            rf = trajopt.FDDP(tol=HOVI_TOL).solve(mpc_problem(H, dt, q0), trajopt.VI(s))
            fddp_times.append(rf.timing["solver"])
        mean = [r["mean_ms"] for r in out["runs"] if r["horizon"] == H and r["s"] == s]
        out["ipopt"].append(dict(horizon=H, s=s, ipopt_first_seconds=times[0], ipopt_best_seconds=min(times),
                                 ipopt_iterations=int(ri.iterations), ipopt_cost=float(ri.cost), ipopt_success=bool(ri.success),
                                 fddp_cold_seconds=min(fddp_times), fddp_cold_iterations=int(rf.iterations), fddp_cold_cost=float(rf.cost),
                                 ratio_ipopt_to_mpc_mean_solve=min(times) / (1e-3 * min(mean))))
        print(f"  IPOPT H={H} s={s}: {min(times):.3f} s ({ri.iterations} it); cold FDDP {min(fddp_times) * 1e3:.2f} ms "
              f"({rf.iterations} it)", flush=True)
    return out


# ----------------------------------------------------------------------------------------------
# E. FDDP through contact
# ----------------------------------------------------------------------------------------------

def part_e(quick):
    from hovi.examples.standing import standing
    st = standing("littledog")
    model, contacts, q0, u0 = st.model, st.contacts, st.q0, st.u
    N, dt = (10, 0.01) if quick else (40, 0.01)
    iters = 3 if quick else 100
    smoothings = (0.0, 1e-8) if quick else (0.0, 1e-10, 1e-8, 1e-6)
    pr = trajopt.Problem(model, N, N * dt, controls="held", u_bounds=(-np.inf, np.inf), q_bounds=(-np.inf, np.inf))
    pr.initial_state(q0)
    qT = q0.copy()
    qT[2] -= 0.03
    pr.add_cost(trajopt.ControlEffort(1e-3))
    ws = np.ones(model.n)
    ws[2] = 0
    pr.add_cost(trajopt.StateTracking(q0, ws, velocity_weight=0.1))
    w = np.zeros(model.n)
    w[2] = 1e4
    pr.add_cost(trajopt.TerminalCost(qT, w, velocity_weight=10.0))
    out = {"scene": "LittleDog standing (hovi.examples.standing) -> base 3 cm lower at the end", "N": N, "dt": dt,
           "max_iterations": iters, "costs": "ControlEffort(1e-3) + StateTracking(q0, 1 except base z, velocity 0.1) + "
           "TerminalCost(base z - 0.03, 1e4, velocity 10)", "guess": "the standing feed-forward u", "rows": []}
    for smoothing in smoothings:
        t0 = time.perf_counter()
        r = trajopt.FDDP(max_iterations=iters, contacts=contacts, smoothing=smoothing).solve(pr, trajopt.VI(1), guess=u0)
        wall = time.perf_counter() - t0
        traj = r.solver["trajectory"]
        row = dict(smoothing=smoothing, status=r.status, converged=bool(r.success), iterations=int(r.iterations), cost=float(r.cost),
                   solver_seconds=float(r.timing["solver"]), wall_seconds=wall, stop=float(r.solver["stop"]),
                   height_change=float(traj.q[-1][2] - q0[2]), min_gap=float(traj.contact.gaps.min()))
        out["rows"].append(row)
        print(f"  smoothing {smoothing:g}: {row['iterations']} it, {row['solver_seconds']:.2f} s, cost {row['cost']:.4f}, "
              f"dz {row['height_change'] * 100:.2f} cm, min gap {row['min_gap']:.1e}, {row['status']}", flush=True)
    return out


# ----------------------------------------------------------------------------------------------
# Tables
# ----------------------------------------------------------------------------------------------

def fmt_t(x):
    return "—" if x is None else (f"{x * 1e3:.1f} ms" if x < 1 else f"{x:.2f} s")


def tables(res):
    lines = []
    a = res.get("A")
    if a:
        lines += ["### A. FDDP on the VI against Crocoddyl's box-FDDP (RK4)", "",
                  f"Solve time on one core (best of up to {res['repeats']}, solvers alternating), iterations, cost, and the "
                  "re-simulation error of the optimised held controls (DOP853 1e-12): over the whole motion from x0 "
                  "(`resim`) and one stage at a time from each knot (`step`), inf-norm on (q, q̇). "
                  "`*`: another local optimum (cost > 1.05 x the best at that N).", ""]
        for name, e in a["swingups"].items():
            lines += [f"**{name}** (T = {e['spec']['T']} s, |u| <= {e['spec']['u_max']})", "",
                      "| N | solver | time | iterations | cost | resim error | step error |", "|---|---|---|---|---|---|---|"]
            for r in e["rows"]:
                lines.append(f"| {r['N']} | {r['solver']} | {fmt_t(r['seconds'])} | {r['iterations']}"
                             f"{'' if r['converged'] else ' (not converged)'} | {r['cost']:.4f}{' *' if r['other_optimum'] else ''} | "
                             f"{r['resim_error']:.1e} | {r['step_error']:.1e} |")
            lines.append("")
        lines += ["Time to reach a re-simulation error (the cheapest N whose error is at or below it):", "",
                  "| swing-up | level | " + " | ".join(["hovi VI s=1", "hovi VI s=2", "hovi VI s=3", "Crocoddyl RK4"]) + " |",
                  "|---|---|---|---|---|---|"]
        for name, e in a["swingups"].items():
            for level, by in e["time_to_reach"].items():
                cells = []
                for s in ["hovi VI s=1", "hovi VI s=2", "hovi VI s=3", "Crocoddyl RK4"]:
                    x = by.get(s)
                    cells.append("not reached" if x is None else
                                 f"{fmt_t(x['seconds'])} (N = {x['N']}{', *' if x['other_optimum'] else ''})")
                lines.append(f"| {name} | {float(level):g} | " + " | ".join(cells) + " |")
        lines.append("")
        if any("tight_stopping" in e for e in a["swingups"].values()):
            lines += ["Where the stopping tests stop (nominal N): cost above the same solver's run to a tight test "
                      "(relative), and hovi with the tolerance at which it stops as close as Crocoddyl (best of 3):", "",
                      "| swing-up | solver | gap at the default test | tol for Crocoddyl's gap | its gap | iterations | time |",
                      "|---|---|---|---|---|---|---|"]
            for name, e in a["swingups"].items():
                t = e.get("tight_stopping", {})
                for s in ["hovi VI s=1", "hovi VI s=2", "hovi VI s=3", "Crocoddyl RK4"]:
                    x = t.get(s)
                    if x is None:
                        continue
                    nominal = [r for r in e["rows"] if r["solver"] == s and r["N"] == e["rows"][0]["N"]]
                    tail = (f"{x['matched_tol']:g} | {x['matched_gap']:.1e} | {x['matched_iterations']} | {fmt_t(x['matched_seconds'])}"
                            if "matched_tol" in x else
                            f"(its default) | {x['relative_gap']:.1e} | {nominal[0]['iterations'] if nominal else '—'} | "
                            f"{fmt_t(nominal[0]['seconds']) if nominal else '—'}")
                    lines.append(f"| {name} | {s} | {x['relative_gap']:.1e} | {tail} |")
            lines.append("")
    b = res.get("B")
    if b:
        lines += ["### B. TVLQR Monte-Carlo on the swing-ups", "",
                  f"{b['runs']} runs per condition; success: {b['success']}. Noise: {b['noise']}; mass: {b['mass']}.", "",
                  "Success, and in brackets the runs with every angle within 0.1 rad of the upright at the end of the "
                  "motion (t = T, before the hold).", "",
                  "| robot | push | condition | open loop | closed loop (TVLQR + LQR) |", "|---|---|---|---|---|"]
        for name, e in b["robots"].items():
            for cond, row in e["conditions"].items():
                lines.append(f"| {name} | {e['push']['impulse_Ns']} N s at the {e['push']['body']} tip, t = {e['push']['time']} s "
                             f"| {cond} | {100 * row['open_loop']['success_rate']:.0f} % ({100 * row['open_loop']['upright_at_end_of_motion_rate']:.0f} %) | "
                             f"{100 * row['closed_loop']['success_rate']:.0f} % ({100 * row['closed_loop']['upright_at_end_of_motion_rate']:.0f} %) |")
        lines.append("")
    c = res.get("C")
    if c:
        lines += ["### C. LQR at the upright: region of attraction", "",
                  f"dt = {c['dt']}, s = {c['s']}, {c['seconds']} s from the offset; success as in B.", ""]
        lines += markdown_table(
            ["robot", "grid", "recovers from (other = 0)", "the same without control limits", "recovers from (first = 0)",
             "grid fraction"],
            [[f"{m['robot']} (u within ±{m['u_limits'][1]:g})",
              f"{AXIS_NAMES[(m['robot'], m['axes'][0])]} x {AXIS_NAMES[(m['robot'], m['axes'][1])]}",
              f"{m['largest_a_at_b0']:.3f}", f"{m['largest_a_at_b0_without_limits']:.3f}", f"{m['largest_b_at_a0']:.3f}",
              f"{100 * m['fraction']:.0f} %"] for m in c["maps"].values()]) + [""]
    d = res.get("D")
    if d:
        lines += ["### D. MPC on the cart-pole at 100 Hz", "",
                  f"Plant {d['plant']}; {d['seconds']} s from q0 = (0.1 m, pi - 0.3 rad); pushes "
                  + ", ".join(f"{p['impulse_Ns']} N s at t = {p['time']} s" for p in d["pushes"]) + " on the pole tip; holds: every plant step converged, the pole never "
                  "beyond pi/2 and within 0.05 rad at the end.", "",
                  "| horizon | s | max it | mean | p95 | worst | > 10 ms | real-time factor | it/solve | pole max after push | pole at end | cart max | holds |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in d["runs"]:
            lines.append(f"| {r['horizon']} ({r['horizon_seconds']:.1f} s) | {r['s']} | {r['max_iterations']} | {r['mean_ms']:.2f} ms | "
                         f"{r['p95_ms']:.2f} ms | {r['worst_ms']:.2f} ms | {r['over_period']} of {r['solves']} | "
                         f"{r['real_time_factor']:.1f} | {r['mean_iterations']:.2f} | {r['max_pole_error_after_push']:.3f} rad | "
                         f"{r['final_pole_error']:.4f} rad | {r['max_cart']:.2f} m | {'yes' if r['holds'] else 'no'} |")
        lines += [""] + markdown_table(
            ["horizon", "s", "IPOPT (first, best)", "IPOPT iterations", "cold FDDP", "FDDP iterations",
             "IPOPT / MPC mean solve"],
            [[r["horizon"], r["s"], f"{fmt_t(r['ipopt_first_seconds'])}, {fmt_t(r['ipopt_best_seconds'])}",
              r["ipopt_iterations"], fmt_t(r["fddp_cold_seconds"]), r["fddp_cold_iterations"],
              f"{r['ratio_ipopt_to_mpc_mean_solve']:.0f}x"] for r in d["ipopt"]]) + [""]
    e = res.get("E")
    if e:
        lines += ["### E. FDDP through contact (LittleDog, 3 cm crouch)", "",
                  f"N = {e['N']}, dt = {e['dt']}, at most {e['max_iterations']} iterations.", "",
                  ]
        lines += markdown_table(["smoothing", "iterations", "stopped", "time", "cost", "height change", "min gap"],
                                [[f"{r['smoothing']:g}", r["iterations"], "converged" if r["converged"] else r["status"],
                                  fmt_t(r["solver_seconds"]), f"{r['cost']:.4f}", f"{100 * r['height_change']:.2f} cm",
                                  f"{r['min_gap']:.1e}"] for r in e["rows"]]) + [""]
    return "\n".join(lines)


def versions():
    import crocoddyl
    import pinocchio
    import scipy
    return {"hovi": getattr(hovi, "__version__", "?"), "crocoddyl": crocoddyl.__version__, "pinocchio": pinocchio.__version__,
            "numpy": np.__version__, "scipy": scipy.__version__}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a small smoke run (well under a minute), no README update")
    ap.add_argument("--only", nargs="+", choices=list("ABCDE"), default=list("ABCDE"))
    ap.add_argument("--repeats", type=int, default=None, help="solves per FDDP timing (default 5; quick 1)")
    ap.add_argument("--tables", action="store_true", help="only rebuild the README tables from results/control.json")
    args = ap.parse_args()
    if args.tables:
        import json
        with open(os.path.join(COMMITTED, "control.json")) as f:
            update_readme_section("control", tables(json.load(f)["results"]))
        return
    repeats = args.repeats or (1 if args.quick else 5)
    t_start = time.perf_counter()
    load_start = os.getloadavg()
    res = {}
    parts = {"A": lambda: part_a(args.quick, repeats), "B": lambda: part_b(args.quick), "C": lambda: part_c(args.quick),
             "D": lambda: part_d(args.quick), "E": lambda: part_e(args.quick)}
    for key in args.only:
        print(f"part {key}", flush=True)
        t0 = time.perf_counter()
        load = os.getloadavg()[0]
        res[key] = parts[key]()
        res[key]["part_seconds"] = time.perf_counter() - t0
        res[key]["load_average_1min"] = [load, os.getloadavg()[0]]  # at the part's start and end
    res["repeats"] = repeats
    name = "control_quick" if args.quick else "control"
    commit = hovi_commit()
    payload = {"quick": args.quick, "parts": args.only, "hovi_commit": commit, "versions": versions(),
               "threads": "one core per solve (Crocoddyl nthreads = 1; hovi FDDP threads = 1; batches threads = 1)",
               "load_average_start": list(load_start), "load_average_end": list(os.getloadavg()),
               "results": res, "wall_seconds": time.perf_counter() - t_start}
    full_path = os.path.join(RESULTS, f"{name}.json")
    merged = not args.quick and args.only != list("ABCDE") and os.path.exists(full_path)
    if merged:  # a full run of some parts: the other parts kept from the last full run
        import json
        with open(full_path) as f:
            old = json.load(f)
        for key, part in old.get("results", {}).items():
            if key in "ABCDE" and key not in res:
                res[key] = part
        payload["parts"] = sorted(k for k in res if k in "ABCDE")
        payload["rerun_parts"] = args.only
        payload["earlier_run"] = {k: old.get(k) for k in ("hovi_commit", "load_average_start", "load_average_end", "wall_seconds")}
    path = write_json(f"{name}.json", json_ready(payload, nonfinite_as_text=True))
    if "C" in res:
        try:
            plot_roa(res["C"], os.path.join(RESULTS, f"{name.replace('control', 'control_roa')}.png"))
        except ImportError:
            print("matplotlib missing: no plot")
    text = tables(res)
    print(text)
    print(f"wrote {path} in {time.perf_counter() - t_start:.1f} s (load {load_start[0]:.2f} -> {os.getloadavg()[0]:.2f})")
    if not args.quick and sorted(k for k in res if k in "ABCDE") == list("ABCDE"):
        update_readme_section("control", text)


if __name__ == "__main__":
    sys.exit(main())
