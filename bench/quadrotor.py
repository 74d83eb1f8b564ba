"""A quadrotor on the free joint under LQR and time-varying LQR (``hovi.examples.models.quadrotor``):
the controllers act on the tangent state (q ⊖ q_ref, p - p_ref), so no attitude is singular.

1. Recovery: one LQR made at hover (1 m up, s = 1, dt = 0.01; weights 10 on position, 1 on
   attitude, 1 on velocity, 0.1 on thrust) started from tilts of 0..180° about three axes (x, y and
   a skew one), 0.5 m off and spinning at 1 rad/s about the body's y, on a plant 20 % heavier with
   another inertia than the design model, with thrust limits of ±15 N and of [0, 10] N per rotor
   (rotors that cannot push down). A run recovers when its tilt is within 0.05 rad of level and its
   position within 0.5 m of the reference over the last second of 8 s. The same design on the
   Euler-angle base (x, y, z, yaw, pitch, roll joints, errors in those coordinates) from the same
   starts about y (pitch), ±15 N: its chart is singular at pitch ±90°.
2. A flip: a full turn about x from open-loop roll-torque pulses (the reference), tracked by
   time-varying LQR on the heavier plant; the miss of its end (the largest entry of q ⊖ q_ref),
   closed and open loop.

    python bench/quadrotor.py [--quick]

Writes bench/results/quadrotor.json (quick: quadrotor_quick.json), docs/images/quadrotor_lqr.png
(full mode) and, in full mode, the section "A quadrotor under LQR" of bench/README.md.
"""
from __future__ import annotations

import os
import warnings

import numpy as np

import hovi
from common import ROOT, markdown_table, publish, save_figure, study_parser, write_json
from free_base import based, to_base, velocity_to_base
from hovi.control import lqr, simulate, tvlqr

DT, T = 0.01, 8.0
WEIGHTS = dict(q_weight=[10, 10, 10, 1, 1, 1], v_weight=1.0, u_weight=0.1)
AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "skew": (1.0, -1.0, 0.5)}
NOMINAL = (1.0, (0.01, 0.01, 0.018))   # the design model's mass and inertia (hovi.examples.models.quadrotor)
HEAVIER = (1.2, (0.013, 0.011, 0.021))  # the plant's


def quadrotor(base: str, mass: float, inertia) -> hovi.Model:
    """A quadrotor (rotors at 0.2 m along ±x, ±y; drag torque 0.02 u) on the free joint or on the
    Euler-angle joints."""
    m = based("body", base, mass=mass, inertia=np.diag(inertia))
    for k, (x, y) in enumerate([(0.2, 0.0), (0.0, 0.2), (-0.2, 0.0), (0.0, -0.2)]):
        m.add_point_wrench("body", force=(0, 0, 1.0), torque=(0, 0, 0.02 * (-1) ** k), point=(x, y, 0.0),
                           frame="body", control=m.add_control())
    return m


def axis_angle(axis, degrees) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    half = np.radians(degrees) / 2
    return np.r_[np.sin(half) * a, np.cos(half)]


def tilt(q: np.ndarray, base: str) -> np.ndarray:
    """The angle (rad) between the body's z axis and the world's, per row of q."""
    if base == "free":
        x, y = q[:, 3], q[:, 4]
        return np.arccos(np.clip(1 - 2 * (x * x + y * y), -1, 1))
    return np.arccos(np.clip(np.cos(q[:, 4]) * np.cos(q[:, 5]), -1, 1))


def recovery(base: str, limits, axes, angles) -> list:
    design = hovi.Integrator(quadrotor(base, *NOMINAL), s=1, dt=DT)
    plant = hovi.Integrator(quadrotor(base, *HEAVIER), s=1, dt=DT)
    q_eq = to_base(base, np.r_[0, 0, 1.0, 0, 0, 0, 1.0])
    policy = lqr(design, q_eq, u_eq=np.full(4, 9.81 / 4), u_limits=limits, **WEIGHTS)
    out = []
    for axis in axes:
        for degrees in angles:
            q_free = np.r_[0.5, -0.3, 1.2, axis_angle(AXES[axis], degrees)]
            row = dict(base=base, limits=list(limits), axis=axis, degrees=degrees)
            try:
                q0 = to_base(base, q_free)
                v0 = velocity_to_base(base, q_free, np.r_[0, 0, 0, 0, 1.0, 0])
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    run = simulate(plant, policy, q0, int(round(T / DT)), qdot0=v0)
            except (ValueError, hovi.ModelError, np.linalg.LinAlgError) as e:
                out.append({**row, "recovered": False, "status": f"cannot start: {str(e)[:60]}"})
                continue
            q = run.trajectory.q
            last = q[-int(round(1 / DT)):]
            recovered = run.converged and len(q) == int(round(T / DT)) + 1 and tilt(last, base).max() < 0.05 and \
                np.abs(last[:, :3] - q_eq[:3]).max() < 0.5
            level = np.flatnonzero(tilt(q, base) > 0.1)
            out.append({**row, "recovered": bool(recovered), "status": "ran" if run.converged else run.failure,
                        "time_to_level": float((level[-1] + 1) * DT) if level.size else 0.0,
                        "tilt": tilt(q, base).tolist() if base == "free" and limits[0] < 0 else None})
    return out


def flip_reference(integ: hovi.Integrator):
    """A flip: 2 m up, a full turn about x from open-loop roll-torque pulses (rotors +y and -y 7 N apart for
    0.15 s, then back); (q0, u (150, 2, 4), the reference trajectory)."""
    K, hover, a = 150, 9.81 / 4, 7.0
    u = np.full((K, 2, 4), hover)
    u[20:35, :, 1] += a
    u[20:35, :, 3] -= a
    u[35:50, :, 1] -= a
    u[35:50, :, 3] += a
    q0 = integ.model.neutral()
    q0[2] = 2.0
    return q0, u, integ.rollout(q0, K, u=u)


def flip() -> dict:
    model = quadrotor("free", *NOMINAL)
    integ = hovi.Integrator(model, s=1, dt=DT)
    q0, u, ref = flip_reference(integ)
    roll = np.unwrap([2 * np.arctan2(q[3], q[6]) for q in ref.q])
    policy = tvlqr(integ, ref, u, q_weight=[10, 10, 10, 2, 2, 2], v_weight=1.0, u_weight=0.05)
    plant = hovi.Integrator(quadrotor("free", *HEAVIER), s=1, dt=DT)
    miss = {}
    for name, pol in (("closed", policy), ("open", policy.without_feedback())):
        run = simulate(plant, pol, q0, len(u))
        miss[name] = float(np.abs(model.difference(ref.q[-1], run.trajectory.q[-1])).max())
    return dict(turn_degrees=float(np.degrees(roll[-1])), miss_closed=miss["closed"], miss_open=miss["open"])


def figure(rows, path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.2))
    t = np.arange(int(round(T / DT)) + 1) * DT
    runs = [r for r in rows if r.get("tilt") and r["axis"] == "x"]
    for i, r in enumerate(runs):
        ax.plot(t[:len(r["tilt"])], np.degrees(r["tilt"]), color=plt.cm.viridis(i / max(1, len(runs) - 1)),
                label=f"{r['degrees']}°")
    ax.set_xlim(0, 4)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("tilt [deg]")
    ax.set_title("One LQR at hover from tilts about x (free base; plant 20 % heavier, ±15 N)")
    ax.title.set_fontsize(9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=4, title="start tilt", title_fontsize=7)
    save_figure(fig, path)


def readme(results) -> str:
    lines = ["Measured by `bench/quadrotor.py` (bench/results/quadrotor.json).", "",
             "LQR at hover from tilted starts (8 s; recovered: tilt < 0.05 rad and position within 0.5 m over the "
             "last second):", ""]
    rows = []
    groups = {}
    for r in results["recovery"]:
        groups.setdefault((r["base"], tuple(r["limits"]), r["axis"]), []).append(r)
    for (base, limits, axis), rs in groups.items():
        ok = [r["degrees"] for r in rs if r["recovered"]]
        failed = [f"{r['degrees']}° ({r['status'] if r['status'] != 'ran' else 'not level'})" for r in rs
                  if not r["recovered"]]
        slowest = max((r.get("time_to_level", 0.0) for r in rs if r["recovered"]), default=float("nan"))
        rows.append([base, f"[{limits[0]:g}, {limits[1]:g}] N", axis, f"{len(ok)}/{len(rs)}",
                     f"{slowest:.2f} s", "; ".join(failed) or "-"])
    lines += markdown_table(["base", "thrust", "axis", "recovered", "slowest to 0.1 rad", "not recovered"], rows)
    f = results["flip"]
    lines += ["", f"A flip ({f['turn_degrees']:.0f}° about x) tracked by time-varying LQR on the heavier plant: its end "
              f"missed by {f['miss_closed']:.3f} closed loop, {f['miss_open']:.2f} open loop (largest entry of "
              "q ⊖ q_ref, m and rad)."]
    return "\n".join(lines)


def main() -> None:
    args = study_parser(__doc__).parse_args()
    angles = [0, 90, 179] if args.quick else list(range(0, 181, 15))
    rows = recovery("free", (-15.0, 15.0), ["skew"] if args.quick else list(AXES), angles)
    if not args.quick:
        rows += recovery("free", (0.0, 10.0), list(AXES), angles)
        rows += recovery("euler", (-15.0, 15.0), ["y"], angles)
    results = dict(recovery=rows, flip=flip())
    if not args.quick:
        figure(rows, os.path.join(ROOT, "docs", "images", "quadrotor_lqr.png"))
    for r in rows:
        r.pop("tilt", None)
    write_json("quadrotor_quick.json" if args.quick else "quadrotor.json", results)
    publish("quadrotor", readme(results), args.quick)


if __name__ == "__main__":
    main()
