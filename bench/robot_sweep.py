"""Every robot users load: each URDF shipped by example-robot-data through hovi and Pinocchio.

For every URDF file of example-robot-data's robots directory: hovi.Model.from_urdf with
base="fixed", and also base="euler" where an example-robot-data loader gives the robot a free
flyer (or the file has no movable joint: a single body, e.g. a drone). Pinocchio builds the same
tree: welded root, or a composite root joint of PX, PY, PZ, RZ, RY, RX (hovi's Euler-angle base,
x, y, z then Z-Y-X Euler angles). At random states (fixed seed) the script compares the mass
matrix, forward dynamics (ABA, random torques) and inverse dynamics (RNEA), relative to the
largest entry; and takes one Galerkin step (s = 1) with hovi and checks it against the discrete
Euler-Lagrange equations of a discrete Lagrangian built from Pinocchio's energies (1/2 v^T M v
with Pinocchio's M, and computePotentialEnergy), differentiated by fourth-order central
differences (their truncation and round-off, not hovi, set that check's 1e-8 tolerance).

Armature: where the loader reads rotor parameters from the SRDF (Talos), Pinocchio's armature
(rotor inertia times gear ratio squared) is set in both libraries. A joint that moves no mass (a
massless finger link, say) makes the mass matrix singular in both; hovi refuses it with a
message that says how to fix it, and the sweep takes the third fix it offers: a small armature
(ARMATURE_FIX) on that joint, in both libraries.

    python bench/robot_sweep.py            # every URDF, results/robot_sweep.json and bench/README.md
    python bench/robot_sweep.py --quick    # a few robots (the test suite)
"""
from __future__ import annotations

import argparse
import os
import re
import sys
import time
from collections import defaultdict

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import ROOT, update_readme_section, write_json  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "tests"))
from del_reference import fd4  # noqa: E402  (the tests' fourth-order central differences)

import hovi  # noqa: E402

RTOL = 1e-10        # mass matrix and dynamics: relative to the largest entry
STEP_TOL = 1e-8     # the step against Pinocchio's DEL equations by finite differences
ARMATURE_FIX = 1e-4  # kg m^2 (or kg): the armature the sweep sets on a joint that moves no mass
STATES = 3
QUICK = ["panda_description/urdf/panda.urdf", "romeo_description/urdf/romeo.urdf",
         "solo_description/robots/solo12.urdf", "hector_description/robots/quadrotor_base.urdf",
         "tiago_description/robots/tiago.urdf"]
FLOATING_ROOT = ("PX", "PY", "PZ", "RZ", "RY", "RX")  # hovi's Euler-angle base, in order


def robots_dir() -> str:
    import example_robot_data as erd
    return os.path.realpath(erd.getModelPath("panda_description"))


def urdf_files(root: str) -> list[str]:
    out = []
    for d, _, files in os.walk(root):
        out += [os.path.relpath(os.path.join(d, f), root) for f in files if f.endswith(".urdf")]
    return sorted(out)


def loaders() -> dict[str, list]:
    """URDF path (relative to the robots directory) -> the example-robot-data loader classes using it."""
    import example_robot_data as erd
    out = defaultdict(list)
    for name, cls in sorted(erd.ROBOTS.items()):
        if cls.urdf_filename:
            out[os.path.join(cls.path, cls.urdf_subpath, cls.urdf_filename)].append((name, cls))
    return out


def srdf_armature(pin, pm, root: str, cls) -> np.ndarray | None:
    """Pinocchio's armature from the loader's SRDF rotor parameters (as example-robot-data sets it)."""
    if not (cls and cls.has_rotor_parameters and cls.srdf_filename):
        return None
    pin.loadRotorParameters(pm, os.path.join(root, cls.path, cls.srdf_subpath, cls.srdf_filename), False)
    return np.multiply(pm.rotorInertia.flat, np.square(pm.rotorGearRatio.flat))


class Twin:
    """A hovi model and Pinocchio's model of the same URDF, with the coordinate maps between them."""

    def __init__(self, pin, h, pm, floating: bool):
        self.pin, self.h, self.pm = pin, h, pm
        names = list(pm.names)
        base = 6 if floating else 0
        assert h.n == pm.nv, f"hovi has {h.n} DoF, Pinocchio nv = {pm.nv}"
        self.jid = [names.index(jn) for jn in h.joint_names[base:]]
        for j in self.jid:
            assert pm.nvs[j] == 1 and pm.nqs[j] in (1, 2), f"joint {names[j]} is not 1-DoF"
        self.base = base
        self.vidx = np.array(list(range(base)) + [pm.idx_vs[j] for j in self.jid])
        self.revolute = np.array(h.joint_types) == "revolute"
        self.pm_data = pm.createData()

    def q_pin(self, q):
        qp = self.pin.neutral(self.pm)
        qp[:self.base] = q[:self.base]  # the composite root: nq = nv = 6, hovi's order
        for i, j in enumerate(self.jid):
            k, x = self.pm.idx_qs[j], q[self.base + i]
            if self.pm.nqs[j] == 2:  # continuous joint: (cos, sin)
                qp[k:k + 2] = np.cos(x), np.sin(x)
            else:
                qp[k] = x
        return qp

    def v_pin(self, v):
        out = np.zeros(self.pm.nv)
        out[self.vidx] = v
        return out

    def v_hovi(self, vp):
        return np.asarray(vp)[self.vidx]

    def random_state(self, rng, speed=1.0):
        q = np.where(self.revolute, rng.uniform(-np.pi, np.pi, self.h.n), rng.uniform(-0.5, 0.5, self.h.n))
        q[:self.base] = rng.uniform(-1.0, 1.0, self.base)  # Euler angles away from pitch = ±pi/2
        return q, rng.uniform(-speed, speed, self.h.n)

    def mass_matrix(self, q):
        M = self.pin.crba(self.pm, self.pm_data, self.q_pin(q))
        M = np.triu(M) + np.triu(M, 1).T
        return M[np.ix_(self.vidx, self.vidx)]

    def set_armature(self, a):
        self.h.armature = a
        self.pm.armature = self.v_pin(a)
        self.pm_data = self.pm.createData()


def relative(got, want) -> float:
    return float(np.abs(np.asarray(got) - want).max() / max(np.abs(want).max(), 1e-300))


def step_check(tw: Twin, rng, dt=1e-3):
    """One hovi step (s = 1) from a random state against Pinocchio's DEL equations: the largest of
    |r^{k,0}| and |p^{k+1} - D_2 L_d|, relative to the momenta, with L_d from Pinocchio's energies."""
    pin, pm = tw.pin, tw.pm
    q0, qd0 = tw.random_state(rng, speed=0.5)
    p0 = tw.mass_matrix(q0) @ qd0
    integ = hovi.Integrator(tw.h, s=1, dt=dt)
    q1, p1, info = integ.step(q0, p0, raise_on_failure=False)
    if not info.converged:
        return info.status, float("nan")
    w, b = integ.weights, integ.differentiation_matrix

    def Ld(x):
        qd = b @ x / dt
        L = 0.0
        for a in range(2):
            qp = tw.q_pin(x[a])
            K = 0.5 * qd[a] @ tw.mass_matrix(x[a]) @ qd[a]
            L += w[a] * dt * (K - pin.computePotentialEnergy(pm, tw.pm_data, qp))
        return L

    D = fd4(Ld, info.control_points, 1e-4)
    scale = max(np.abs(p0).max(), np.abs(p1).max(), 1e-300)
    return "converged", float(max(np.abs(p0 + D[0]).max(), np.abs(p1 - D[1]).max()) / scale)


NO_MASS = re.compile(r"joint '([^']+)' moves no mass")


def pinocchio_model(pin, path: str, base: str):
    if base == "fixed":
        return pin.buildModelFromUrdf(path)
    root_joint = pin.JointModelComposite()
    for kind in FLOATING_ROOT:
        root_joint.addJoint(getattr(pin, f"JointModel{kind}")())
    return pin.buildModelFromUrdf(path, root_joint)


def compare(pin, root: str, rel: str, base: str, cls, rng) -> dict:
    row = {"urdf": rel, "base": base, "n": None, "armature": None, "status": None, "message": ""}
    path = os.path.join(root, rel)
    t0 = time.perf_counter()
    try:
        pm, pin_error = pinocchio_model(pin, path, base), ""
    except Exception as e:  # noqa: BLE001 (any Pinocchio failure is recorded, not raised)
        pm, pin_error = None, f"{type(e).__name__}: {e}"
    try:
        h = hovi.Model.from_urdf(path, base=base)
    except (hovi.URDFError, hovi.ModelError) as e:
        row.update(status="refused", message=f"{type(e).__name__}: {e}",
                   pinocchio="refuses it too" if pm is None else "loads it")
        return row
    row["n"] = h.n
    if pm is None:
        row.update(status="pinocchio_failed", message=pin_error)
        return row
    tw = Twin(pin, h, pm, base == "euler")
    armature = np.zeros(h.n)
    a_srdf = srdf_armature(pin, pm, root, cls)
    if a_srdf is not None:
        armature = tw.v_hovi(a_srdf)
        row["armature"] = f"SRDF rotor parameters on {np.count_nonzero(armature)} joints"
    tw.set_armature(armature)
    states = [tw.random_state(rng) for _ in range(STATES)]
    fixed = []
    for q, v in states:  # a joint that moves no mass: hovi says how to fix it; take the armature fix
        while True:
            try:
                h.forward_dynamics(q, v)
                break
            except hovi.ModelError as e:
                joint = NO_MASS.search(str(e))
                if not joint or joint.group(1) in fixed:
                    row.update(status="refused", message=f"ModelError: {e}")
                    return row
                if not row["message"]:
                    row["message"] = f"ModelError: {e}"
                fixed.append(joint.group(1))
                armature[h.joint_index(joint.group(1))] = ARMATURE_FIX
                tw.set_armature(armature)
    if fixed:
        row["armature"] = f"{ARMATURE_FIX:g} on {len(fixed)} joints that move no mass: " + ", ".join(fixed)
    err = {"M": 0.0, "FD": 0.0, "ID": 0.0}
    for q, v in states:
        qp, vp = tw.q_pin(q), tw.v_pin(v)
        err["M"] = max(err["M"], relative(h.mass_matrix(q), tw.mass_matrix(q)))
        tau = rng.uniform(-10, 10, h.n)
        err["FD"] = max(err["FD"], relative(h.forward_dynamics(q, v, tau),
                                            tw.v_hovi(pin.aba(pm, tw.pm_data, qp, vp, tw.v_pin(tau)))))
        acc = rng.uniform(-5, 5, h.n)
        err["ID"] = max(err["ID"], relative(h.inverse_dynamics(q, v, acc),
                                            tw.v_hovi(pin.rnea(pm, tw.pm_data, qp, vp, tw.v_pin(acc)))))
    step_status, step_err = step_check(tw, rng)
    ok = max(err.values()) <= RTOL and step_status == "converged" and step_err <= STEP_TOL
    row.update(status="match" if ok else "mismatch", max_rel_M=err["M"], max_rel_FD=err["FD"], max_rel_ID=err["ID"],
               step_status=step_status, step_rel_residual=step_err, seconds=time.perf_counter() - t0)
    return row


def cases(root: str, quick: bool):
    """(urdf, base, loader class or None, loader names) for every file, fixed and where it applies on the Euler-angle base."""
    by_file = loaders()
    for rel in urdf_files(root):
        if quick and rel not in QUICK:
            continue
        users = by_file.get(rel, [])
        cls = users[0][1] if users else None
        names = [name for name, _ in users]
        yield rel, "fixed", cls, names
        if any(c.free_flyer for _, c in users) or hovi_has_no_joint(os.path.join(root, rel)):
            yield rel, "euler", cls, names


def hovi_has_no_joint(path: str) -> bool:
    try:
        hovi.Model.from_urdf(path)
    except hovi.URDFError as e:
        return "has no movable joint" in str(e)
    return False


def table(rows) -> list[str]:
    """One line per URDF file: the fixed and floating results, the worst differences, and the
    armature the sweep set or the refusal's message."""
    out = ["| URDF (example-robot-data loaders) | n (fixed / euler) | fixed | euler | max rel. diff M, FD, ID | step residual | "
           "armature set, or the refusal |", "|---|---|---|---|---|---|---|"]
    by_file = defaultdict(dict)
    for r in rows:
        by_file[r["urdf"]][r["base"]] = r
    for rel, cases_ in by_file.items():
        fixed, floating = cases_["fixed"], cases_.get("euler")
        both = [r for r in (fixed, floating) if r]
        compared = [r for r in both if r["status"] in ("match", "mismatch")]
        diff = max((max(r["max_rel_M"], r["max_rel_FD"], r["max_rel_ID"]) for r in compared), default=None)
        step = max((r["step_rel_residual"] for r in compared), default=None)
        notes = sorted({r["armature"] for r in compared if r["armature"]} |
                       {f"{r['message']} (Pinocchio {r['pinocchio']})" for r in both if r["status"] == "refused"} |
                       {r["message"] for r in both if r["status"] == "pinocchio_failed"})
        name = rel + (f" ({', '.join(fixed['loaders'])})" if fixed["loaders"] else "")
        n = " / ".join(str(r["n"] or "-") for r in both)
        out.append(f"| {name} | {n} | {fixed['status']} | {floating['status'] if floating else ''} | "
                   f"{'' if diff is None else f'{diff:.1e}'} | {'' if step is None else f'{step:.1e}'} | "
                   f"{'; '.join(notes).replace('|', '/')} |")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help=f"{len(QUICK)} robots")
    args = ap.parse_args()
    import pinocchio as pin
    root = robots_dir()
    rng = np.random.default_rng(14)
    t0 = time.perf_counter()
    rows = []
    for rel, base, cls, names in cases(root, args.quick):
        row = compare(pin, root, rel, base, cls, rng)
        row["loaders"] = names
        rows.append(row)
        print(f"{rel:62s} {base:8s} {row['status']:16s} {row.get('armature') or ''} {row['message'][:90]}", flush=True)
    counts = defaultdict(int)
    for r in rows:
        counts[r["status"]] += 1
    matched = [r for r in rows if r["status"] == "match"]
    refused = [r for r in rows if r["status"] == "refused"]
    worst = {k: max((r[k] for r in matched), default=float("nan"))
             for k in ("max_rel_M", "max_rel_FD", "max_rel_ID", "step_rel_residual")}
    payload = {"files": len({r["urdf"] for r in rows}), "cases": len(rows), "counts": dict(counts),
               "worst_of_matches": worst, "rtol": RTOL, "step_tol": STEP_TOL, "armature_fix": ARMATURE_FIX,
               "pinocchio": pin.__version__, "seconds": time.perf_counter() - t0, "rows": rows}
    path = write_json("robot_sweep_quick.json" if args.quick else "robot_sweep.json", payload)
    print(f"{len(rows)} cases from {payload['files']} URDFs: {dict(counts)}; worst of the matches {worst}; {path}")
    bad = [r for r in rows if r["status"] in ("mismatch", "pinocchio_failed") or
           (r["status"] == "refused" and not hint(r["message"]))]
    if not args.quick:
        summary = (f"{len(rows)} cases ({payload['files']} URDF files, {counts['match']} + {counts['refused']} + "
                   f"{counts['mismatch']} + {counts['pinocchio_failed']}: match, refused, mismatch, Pinocchio failed) "
                   f"in {payload['seconds']:.0f} s, Pinocchio {pin.__version__}. Worst of the matches: mass matrix "
                   f"{worst['max_rel_M']:.1e}, forward dynamics {worst['max_rel_FD']:.1e}, inverse dynamics "
                   f"{worst['max_rel_ID']:.1e} (relative to the largest entry), step residual under Pinocchio's "
                   f"L_d {worst['step_rel_residual']:.1e}. {len(refused)} refused, each with the fix in its message.")
        update_readme_section("robot_sweep", "\n".join(table(rows) + ["", summary]))
    if bad:
        sys.exit(f"{len(bad)} cases neither match Pinocchio nor are refused with a fix: "
                 + "; ".join(f"{r['urdf']} ({r['base']}): {r['status']} {r['message'][:120]}" for r in bad))


def hint(message: str) -> bool:
    """Does a refusal say what to do (or what is wrong with the file, for a malformed one)?"""
    return any(k in message for k in (": give", "correct the", "load it with", "set an armature", "malformed"))


if __name__ == "__main__":
    main()
