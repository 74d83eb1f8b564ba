"""Impacts and order in the contact simulator (hovi.Integrator with contacts): a tumbling rod in
the x-z plane (a planar base x, z, pitch at one end of the rod, so that the mass matrix depends on
the pitch and the flight is nonlinear in these coordinates; the contact point at the other end)
falls, turning, until its free end strikes frictionless ground. Its flight is known in closed form
(the centre of mass on a parabola, the pitch at constant rate), and so is the impact time (the
first root of the end's height). Measured against it for s = 1 without impact location (the trajectory optimiser's time
stepping: the impact happens at the next knot) and s = 1, 2, 3 with it (``locate_impacts``):
the flight's error at the last knot before the impact (order 2s), the error of the impact time
(where the contact's impulse acts), and the rod's horizontal momentum just after the impact
(frictionless ground: it keeps its value).

    python bench/contact_order.py [--quick]
"""
from __future__ import annotations

import argparse

import numpy as np

import hovi
from hovi.contact import Contacts, Terrain
from common import loglog_slope, machine, write_json

G, L, MASS, I_ROD = 9.81, 0.5, 1.0, 1.0 / 12 * 0.5 ** 2   # a 0.5 m rod of 1 kg: I = m L^2 / 12
Z0, PITCH0, VX0, VZ0, RATE0 = 0.6, 0.3, 0.4, 0.5, 4.0           # the throw
FLOOR = 1e-11                                                    # errors below it are round-off: not fitted


def rod():
    m = hovi.Model()
    m.add_body("x", None, "prismatic", axis=(1, 0, 0))
    m.add_body("z", "x", "prismatic", axis=(0, 0, 1))
    m.add_body("rod", "z", "revolute", axis=(0, 1, 0), mass=MASS, com=(0.0, 0.0, -L / 2),
               inertia=np.diag([I_ROD, I_ROD, 1e-6]))
    return m


def end_point(q):
    """The world position (x, z) of the rod's free end (0, 0, -L) at q = (x, z, pitch)."""
    x, z, th = q
    return np.array([x - L * np.sin(th), z - L * np.cos(th)])


def exact(t):
    """The closed-form flight at times t: q (len(t), 3) (the centre of mass, L/2 from the joint, on its
    parabola; the pitch at constant rate)."""
    t = np.asarray(t, float)
    th = PITCH0 + RATE0 * t
    cx, cz = VX0 * t, Z0 + VZ0 * t - G * t ** 2 / 2
    return np.stack([cx + L / 2 * np.sin(th), cz + L / 2 * np.cos(th), th], axis=-1)


def exact_velocity0():
    """q̇ at t = 0 of the closed form."""
    return np.array([VX0 + L / 2 * np.cos(PITCH0) * RATE0, VZ0 - L / 2 * np.sin(PITCH0) * RATE0, RATE0])


def exact_impact():
    """The first time the end's height reaches 0, by bisection on the closed form."""
    ts = np.linspace(0, 2, 20001)
    z = np.array([end_point(q)[1] for q in exact(ts)])
    k = int(np.argmax(z < 0))
    lo, hi = ts[k - 1], ts[k]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if end_point(exact([mid])[0])[1] > 0 else (lo, mid)
    return 0.5 * (lo + hi)


def run(s, dt, locate, t_impact):
    model = rod()
    contacts = Contacts(model, [("rod", (0.0, 0.0, -L))], Terrain(), mu=0.0, plane="xz")
    integ = hovi.Integrator(model, s=s, dt=dt, contacts=contacts, locate_impacts=locate)
    steps = int(np.ceil((t_impact + 0.05) / dt))
    traj = integ.rollout(exact([0])[0], steps, qdot0=exact_velocity0())
    k_imp = int(np.argmax(traj.contact.active[:, 0]))           # the step whose impulses stop the end
    before = k_imp                                               # knot k_imp: still in flight (the impact is after it)
    flight_error = float(np.abs(traj.q[before] - exact([traj.t[before]])[0]).max())
    theta = traj.contact.impact[k_imp] if traj.contact.impact is not None else 0.0
    t_hit = traj.t[k_imp] + (theta if theta > 0 else 1.0) * dt    # where the impulse acts: inside the step, or its end
    # just after: the rod's horizontal momentum (frictionless ground: no horizontal impulse, so the
    # centre of mass keeps VX0)
    p_x = float(traj.p[k_imp + 1][0])
    return {"s": s, "dt": dt, "locate": locate, "flight_error": flight_error,
            "impact_time_error": float(abs(t_hit - t_impact)), "px_after_error": abs(p_x - MASS * VX0)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    t_impact = exact_impact()
    dts = [0.02, 0.01] if args.quick else [0.04, 0.02, 0.01, 0.005, 0.0025]
    rows = []
    for s, locate in [(1, False), (1, True), (2, True), (3, True)]:
        for dt in dts:
            rows.append(run(s, dt, locate, t_impact))
    out = {"machine": machine(), "t_impact": t_impact, "rows": rows, "slopes": {}}
    print(f"exact impact at t = {t_impact:.12f} s")
    print(f"{'s':>2} {'located':>8} {'dt':>7} {'flight error':>13} {'impact time error':>18} {'p_x error after':>16}")
    for r in rows:
        print(f"{r['s']:>2} {str(r['locate']):>8} {r['dt']:>7.4f} {r['flight_error']:>13.3e} {r['impact_time_error']:>18.3e} "
              f"{r['px_after_error']:>16.3e}")
    for s, locate in [(1, False), (1, True), (2, True), (3, True)]:
        sel = [r for r in rows if r["s"] == s and r["locate"] == locate]
        key = f"s={s}{' located' if locate else ''}"
        def slope(field):  # over the errors above round-off (1e-11)
            pts = [(r["dt"], r[field]) for r in sel if r[field] > FLOOR]
            return loglog_slope(*zip(*pts)) if len(pts) >= 2 else float("nan")
        out["slopes"][key] = {"flight": slope("flight_error"), "impact_time": slope("impact_time_error")}
        print(f"{key}: flight error order {out['slopes'][key]['flight']:.2f}, impact time error order "
              f"{out['slopes'][key]['impact_time']:.2f}")
    print("wrote", write_json("contact_order_quick.json" if args.quick else "contact_order.json", out))


if __name__ == "__main__":
    main()
