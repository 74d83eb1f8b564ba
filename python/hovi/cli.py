"""The ``hovi`` command line: ``hovi simulate`` (the main job), ``hovi optimize`` and ``hovi info``."""
from __future__ import annotations

import argparse
import json
import os
import sys
import threading
import time
import warnings
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from . import Model, __version__
from .contact import DEFAULT_FRICTION, Contacts
from .examples import MODEL, OPTIMIZATION, ROBOT, ROBOT_EXAMPLE, entries, get, names
from .integrator import ConvergenceError, Integrator


class ModelSpecError(ValueError):
    """A model argument that is neither an existing URDF file nor a built-in name (one-line message)."""


def model_listing() -> str:
    """What ``hovi simulate`` and ``hovi info`` take, from the registry of examples."""
    return (f"'pendulum' or 'pendulum:N' (the built-in N-link pendulum, N >= 1), a built-in model "
            f"({', '.join(names(MODEL)[1:])}), a robot ({', '.join(names(ROBOT))}) or the path of a URDF file")


def resolve_model(spec: str, base: Optional[str] = None) -> Tuple[Model, str]:
    """The model named by ``spec`` and how its root is attached to the world ('fixed', 'floating'
    or 'planar'; ``base``, default 'fixed', for a URDF file): a path if that file exists, else a
    built-in by its exact name ('pendulum', 'pendulum:N', a model or a robot of ``hovi.examples``),
    whose base is its own. ModelSpecError with a one-line message saying what is wrong and what is
    accepted otherwise (also for a ``base`` other than a built-in's own)."""
    accepted = "accepted: " + model_listing()
    if os.path.isdir(spec):
        raise ModelSpecError(f"model '{spec}' is a directory, not a URDF file; {accepted}")
    if os.path.isfile(spec):
        return load_urdf(spec, base or "fixed"), base or "fixed"
    model, own = built_in_model(spec, accepted)
    if base is not None and base != own:
        raise ModelSpecError(f"argument --base: the built-in '{spec}' has {base_words(own)}; --base {base} applies to "
                             "URDF files")
    return model, own


def built_in_model(spec: str, accepted: str) -> Tuple[Model, str]:
    """The built-in model named ``spec`` and its own base (see resolve_model)."""
    name, colon, n = spec.partition(":")
    if name == "pendulum":
        if not colon:
            return get(MODEL, "pendulum").build(32), "fixed"
        if not n.isdigit() or int(n) < 1:
            raise ModelSpecError(f"model '{spec}': N in 'pendulum:N' must be a whole number of links >= 1, "
                                 f"got '{n}'")
        return get(MODEL, "pendulum").build(int(n)), "fixed"
    if spec in entries(MODEL):
        return get(MODEL, spec).build(), "fixed"
    if spec in entries(ROBOT):
        robot = get(ROBOT, spec).build()
        return robot.model, robot.base
    if spec.lower().endswith((".urdf", ".xml", ".xacro")) or os.sep in spec:
        raise ModelSpecError(f"model file '{spec}' not found; {accepted}")
    raise ModelSpecError(f"unknown model '{spec}' (no such file or built-in name); {accepted}")


def load_urdf(path: str, base: str) -> Model:
    """A URDF file as a Model; a one-line ModelSpecError for an MJCF file, malformed XML (with its
    line) or anything the URDF parser refuses."""
    import xml.etree.ElementTree as ET
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        line = e.position[0] if getattr(e, "position", None) else None
        where = f" at line {line}" if line else ""
        raise ModelSpecError(f"'{path}' is not well-formed XML{where} ({e}); hovi reads URDF files "
                             f"(root element <robot>)") from None
    except UnicodeDecodeError:
        raise ModelSpecError(f"'{path}' is not a text XML file; hovi reads URDF files (root element <robot>)") from None
    if root.tag == "mujoco":
        raise ModelSpecError(f"'{path}' is an MJCF (MuJoCo) file, root element <mujoco>; hovi reads URDF files "
                             f"(root element <robot>): convert it to URDF first")
    if root.tag != "robot":
        raise ModelSpecError(f"'{path}' has root element <{root.tag}>; hovi reads URDF files (root element <robot>)")
    try:
        return Model.from_urdf(path, base=base)
    except ValueError as e:  # hovi.URDFError / ModelError: the link or joint at fault
        raise ModelSpecError(f"'{path}': " + " ".join(str(e).split())) from None


def load_model(spec: str, base: Optional[str] = None) -> Model:
    """The model named by ``spec`` (see resolve_model)."""
    return resolve_model(spec, base)[0]


def initial_state(model: Model, spread: float, seed: int):
    """q0 moved from the neutral configuration by a velocity uniform in [-spread, spread] per joint
    (clipped to joint limits; a free base turned by it), zero velocity."""
    rng = np.random.default_rng(seed)
    v = rng.uniform(-spread, spread, model.n)
    lo, hi = model.lower_limits, model.upper_limits
    v = np.clip(v, np.where(np.isfinite(lo), lo, -np.inf), np.where(np.isfinite(hi), hi, np.inf))
    return model.integrate(model.neutral(), v)


#: The built-in robots that stand on their terrain in ``hovi simulate`` unless --no-ground
#: (``hovi.examples.standing``: joint PD about the nominal pose and static feed-forward torques).
STANDING = ("spring_flamingo", "littledog", "atlas")
DROP = 0.03      # m: how far above the ground the lowest contact point starts (--drop)
GROUND_DT = 0.005  # s: the time step with the ground without --dt (the standing scenes')


@dataclass
class GroundScene:
    """What ``hovi simulate`` runs on the ground: the integrator with its contacts, the initial
    state, the controls, and what the report and the animation need."""
    model: Model           # the simulated model (a robot's: with its PD springs and dampers)
    integrator: Integrator
    contacts: Contacts
    q0: np.ndarray
    u: Optional[np.ndarray]
    names: List[str]       # of the contacts
    what: str              # one line: what is simulated


def base_words(base: str) -> str:
    """'a fixed base', 'a floating base', 'an Euler-angle floating base' or 'a planar base'."""
    return "an Euler-angle floating base" if base == "euler" else f"a {base} base"


def base_coordinates(base: str) -> Tuple[int, int]:
    """(number of base coordinates in q, index of the base's height z) of a 'floating' (x, y, z and a
    quaternion), 'euler' (x, y, z, yaw, pitch, roll) or 'planar' (x, z, pitch) base; (0, -1) for 'fixed'."""
    return {"floating": (7, 2), "euler": (6, 2), "planar": (3, 1)}.get(base, (0, -1))


def wants_ground(args, spec_is_robot: bool) -> bool:
    """Whether to simulate on the ground: --ground, --no-ground, else for the built-in robots and
    when --contact or --mu is given. ValueError naming the flag for --contact or --mu with --no-ground."""
    given = {"--contact": bool(args.contact), "--mu": args.mu is not None}
    if args.ground is False:
        for flag, value in given.items():
            if value:
                raise ValueError(f"argument {flag}: contact needs the ground; leave out --no-ground (or {flag})")
        return False
    return bool(args.ground) or spec_is_robot or any(given.values())


def lift(contacts: Contacts, q0: np.ndarray, base: str, drop: float) -> np.ndarray:
    """q0 with the base's height set so that the lowest contact point is ``drop`` m above the
    terrain; a fixed base cannot be lifted: ValueError if a contact point starts below it."""
    q0 = q0.copy()
    gaps = contacts.gaps(q0)
    _, z = base_coordinates(base)
    if z >= 0:
        q0[z] += drop - float(gaps.min())
    elif gaps.min() < 0:
        raise ValueError(f"argument --contact: the contact points start below the ground (the lowest "
                         f"{-gaps.min():.3g} m under it) and a fixed base cannot be lifted; give a lower "
                         f"--ground-height, or another --seed or --spread")
    return q0


def ground_scene(args, model: Model, base: str, robot_name: Optional[str]) -> GroundScene:
    """The contact simulation of ``hovi simulate`` with the ground: a built-in robot's standing
    scene (``hovi.examples.standing``) dropped from --drop, or the model with the --contact points,
    its joints at random (--spread, --seed) and its base lifted to --drop above the ground.
    ValueError naming the flag for what is missing or wrong."""
    from .contact import Terrain
    from .contact.contacts import friction_coefficient
    s = 1 if args.s is None else args.s  # above 1: impacts located on the step's polynomial
    mu = DEFAULT_FRICTION if args.mu is None else friction_coefficient(args.mu, "--mu")
    plane = "xz" if base == "planar" else ""
    rng = np.random.default_rng(args.seed)
    nb, _ = base_coordinates(base)
    if robot_name is not None:
        from .examples.standing import standing
        if args.contact:
            raise ValueError(f"argument --contact: the built-in robot '{robot_name}' has its feet as its contact "
                             f"points; --contact is for a URDF file or another model")
        st = standing(robot_name, dt=args.dt, mu=mu, ground=args.ground_height, s=s)
        integ, contacts = st.integrator, st.contacts
        q0 = st.q0.copy()
        spread = 0.0 if args.spread is None else args.spread
        q0[nb:] += rng.uniform(-spread, spread, model.nq - nb)
        return GroundScene(st.model, integ, contacts, lift(contacts, q0, base, args.drop), st.u,
                           [c.name for c in st.robot.contacts],
                           f"standing on the ground (joint PD about its standing pose and static feed-forward "
                           f"torques, hovi.examples.standing), dropped from {args.drop:g} m; mu = {mu:g}")
    if not args.contact:
        raise ValueError(f"the ground needs contact points: give --contact LINK:x,y,z (repeatable; a point of a link "
                         f"in the link's frame, m) and optionally --mu (default {DEFAULT_FRICTION:g}); the model's links: "
                         f"{', '.join(model.body_names)}")
    for link, _ in args.contact:
        if link not in model.body_names:
            raise ValueError(f"argument --contact: no link '{link}' in this model; its links: "
                             f"{', '.join(model.body_names)}" + (" (the root link of a fixed base is the world)"
                                                                 if base == "fixed" else ""))
    contacts = Contacts(model, list(args.contact), Terrain(ground=args.ground_height), mu=mu, plane=plane)
    dt = GROUND_DT if args.dt is None else args.dt
    integ = Integrator(model, s=s, dt=dt, tol=args.tol, contacts=contacts)
    q0 = initial_state(model, np.pi / 12 if args.spread is None else args.spread, args.seed)
    q0[:nb] = model.neutral()[:nb]
    return GroundScene(model, integ, contacts, lift(contacts, q0, base, args.drop), None,
                       [f"{link}_{i}" for i, (link, _) in enumerate(args.contact)],
                       f"on the ground with {len(args.contact)} contact point(s), mu = {mu:g}"
                       + (f", dropped from {args.drop:g} m" if base != "fixed" else ""))


def cmd_simulate(args) -> int:
    model, base = resolve_model(args.model, args.base)
    robot_name = args.model if not os.path.isfile(args.model) and args.model in STANDING else None
    scene = ground_scene(args, model, base, robot_name) if wants_ground(args, robot_name is not None) else None
    if scene is None:
        if args.s is None:
            args.s = 2
        dt = 0.01 if args.dt is None else args.dt
        integ = Integrator(model, s=args.s, dt=dt, tol=args.tol)
        q0 = initial_state(model, np.pi / 12 if args.spread is None else args.spread, args.seed)
        u = None
    else:
        model, integ, q0, u = scene.model, scene.integrator, scene.q0, scene.u
        dt = integ.dt
    steps = int(round(args.duration / dt))
    print(f"{args.model}: {model.n} DoF, {model.total_mass:.4g} kg; s = {integ.s} (order {integ.order}), "
          f"dt = {dt} s, {steps} steps" + ("" if scene is None else f"; {scene.what}"))
    if base != "fixed" and scene is None:
        print(free_fall_note(model, base, steps * dt, robot_name is not None))
    for p in args.push:
        print(f"push: {p.body} at t = {p.time:g} s, impulse {list(p.impulse)} N s"
              + (f", angular impulse {list(p.angular)} N m s" if any(p.angular) else ""))
    t0 = time.perf_counter()
    if args.push:
        traj = pushed_run(integ, q0, u, steps, args.push)
        if traj.steps == 0:
            return 1
    else:
        try:
            traj = integ.rollout(q0, steps, u=u, progress=not args.no_progress)
        except ConvergenceError as e:
            print(f"error: {e}", file=sys.stderr)
            traj = e.trajectory
            if traj is None or traj.steps == 0:
                return 1
    wall = time.perf_counter() - t0
    # the speed figure is the C++ loop's own time (Trajectory.solve_seconds): not the progress bar,
    # its import or the Python between chunks, which wall_time_s includes
    solve = traj.solve_seconds if traj.solve_seconds > 0 else wall
    energy = traj.energy
    rel = np.abs(energy - energy[0]) / max(abs(energy[0]), 1e-300)
    summary = {
        "model": args.model, "dof": model.n, "s": integ.s, "dt": dt, "steps": traj.steps,
        "solve_seconds": solve, "wall_time_s": wall, "steps_per_second": traj.steps / solve,
        "newton_iterations_mean": float(traj.iterations.mean()), "newton_iterations_max": int(traj.iterations.max()),
        "factorizations_mean": float(traj.factorizations.mean()),
        "energy_initial": float(energy[0]), "energy_final": float(energy[-1]),
        "energy_error_max_relative": float(rel.max()),
        "energy_error_final_relative": float(rel[-1]), "converged": traj.converged, "ground": scene is not None,
        "pushes": [dict(body=p.body, time=p.time, impulse=list(p.impulse), angular=list(p.angular)) for p in args.push],
    }
    print(f"{summary['steps_per_second']:.0f} steps/s ({solve:.3g} s in the integrator; {wall:.3g} s wall"
          f"{'' if args.no_progress else ' with the progress bar'}), Newton iterations per step: "
          f"mean {summary['newton_iterations_mean']:.2f}, max {summary['newton_iterations_max']} "
          f"(Jacobian factorisations per step: mean {summary['factorizations_mean']:.2f})")
    if scene is None:
        print(f"energy E0 = {energy[0]:.6g} J, max relative error {rel.max():.2e}, final {rel[-1]:.2e}")
    else:
        print(f"energy E0 = {energy[0]:.6g} J, final {energy[-1]:.6g} J (not conserved on the ground: impacts, "
              f"friction and any dampers dissipate it)")
        summary.update(contact_report(scene, traj, base))
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "simulate.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if not args.no_plot:
        from .vis.plots import plot_configuration, plot_contact_forces, plot_energy_error
        name = os.path.basename(args.model)
        if scene is None:
            first = "energy_error.png"
            plot_energy_error(traj.t, energy, os.path.join(args.output, first),
                              f"{name}, s = {integ.s}, dt = {dt} s")
        else:
            first = "contact_forces.png"
            c = traj.contact
            plot_contact_forces(traj.t[:c.normal.shape[0]], c.world_impulses[..., 2] / dt, summary["weight"],
                                os.path.join(args.output, first), scene.names, f"{name} on the ground, dt = {dt} s")
        scenery = (dict(terrain=scene.contacts.terrain, arrows=contact_arrows(scene, traj, summary["weight"]))
                   if scene is not None else dict(ground=None if base == "fixed" else 0.0))
        plot_configuration(model, traj.q[-1], os.path.join(args.output, "final_configuration.png"),
                           f"{name} at t = {traj.t[-1]:.3g} s", pushes=args.push or None, **scenery)
        print(f"wrote {args.output}/{first}, final_configuration.png, simulate.json")
    if args.animate:
        if scene is None:
            write_animation(model, traj, args, ground=None if base == "fixed" else 0.0)
        else:
            write_animation(model, traj, args, terrain=scene.contacts.terrain,
                            arrows=contact_arrows(scene, traj, summary["weight"]))
    if not traj.converged:
        print(f"FAILED: the run stopped at step {traj.steps} of {steps} (t = {traj.t[-1]:.4g} s): {traj.status[-1]}",
              file=sys.stderr)
    return 0 if traj.converged else 1


def contact_arrows(scene: GroundScene, traj, weight: float):
    """The contact forces of a rollout on the ground as arrows (hovi.vis.video.ForceArrows)."""
    from .vis.video import ForceArrows
    return ForceArrows.from_contacts(traj, scene.contacts, weight, names=scene.names)


def pushed_run(integ: Integrator, q0: np.ndarray, u: Optional[np.ndarray], steps: int, pushes: list):
    """The rollout of ``hovi simulate --push``: the held controls u (none: zero) as an open-loop
    ``hovi.control.Policy`` in the C++ closed loop, which applies the pushes; a failed step ends it
    (an error line says which)."""
    from .control import Policy, simulate
    m = integ.model.n_controls
    if m == 0:
        raise ValueError("argument --push: pushes run in hovi.control's closed loop, which needs a model with "
                         "controls; this one has none")
    for p in pushes:
        p.knots(integ.model, integ.dt)  # the body named, or a one-line error naming it
    policy = Policy.open_loop(np.zeros((1, m)) if u is None else np.atleast_2d(u), integ.dt, integ.s, integ.n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # said below, as a rollout's failure is
        run = simulate(integ, policy, q0, steps, pushes=pushes)
    if run.failure is not None:
        print(f"error: {run.failure}", file=sys.stderr)
    return run.trajectory


def below_ground(model: Model, q: np.ndarray, ground: float) -> List[Tuple[str, float]]:
    """(name, height) of the bodies whose joint frame is below the ground at q: only the contact points
    touch the terrain, so a body that falls through it is named rather than drawn over."""
    z = model.joint_placements(q)[:, 2, 3]
    return [(name, float(h)) for name, h in zip(model.body_names, z) if h < ground - 1e-6]


def contact_report(scene: GroundScene, traj, base: str) -> dict:
    """Print and return the contact figures of a rollout on the ground: the landing time (the first
    step with a contact impulse), the deepest penetration (min of the gaps), the contact force at
    the end against the weight, and how far the base moved in the last second (or half, if shorter)."""
    c, dt = traj.contact, traj.t[1] - traj.t[0]
    model = scene.model
    weight = float(model.total_mass * np.linalg.norm(np.asarray(model.gravity, dtype=float)))
    touched = np.flatnonzero(c.active.any(axis=1))
    landing = float(traj.t[touched[0]]) if len(touched) else None
    gap_min = float(c.gaps.min())
    force = c.world_impulses[-1].sum(axis=0) / dt
    active = int(c.active[-1].sum())
    out = {"contacts": len(scene.names), "landing_time": landing, "gap_min": gap_min,
           "max_penetration": max(0.0, -gap_min), "contact_force_end": force.tolist(), "weight": weight,
           "weight_carried": float(force[2] / weight), "active_contacts_end": active}
    if landing is None:
        print(f"no contact in {traj.t[-1]:.3g} s: the lowest contact point stays {gap_min:.3g} m or more above the ground")
    else:
        print(f"landed at t = {landing:.4g} s; deepest penetration {max(0.0, -gap_min):.2e} m (smallest gap "
              f"{gap_min:.2e} m)")
    print(f"at the end: contact force {force[2]:.6g} N up ({force[2] / weight:.6f} of the weight, {weight:.6g} N) on "
          f"{active} of {len(scene.names)} contacts; horizontal {np.hypot(force[0], force[1]):.3g} N")
    nb, z = base_coordinates(base)
    if nb:
        position = [0, 1, 2] if base in ("floating", "euler") else [0, 1]
        k0 = max(0, traj.steps - int(round(min(1.0, traj.t[-1] / 2) / dt)))  # the last second, or half
        moved = float(np.linalg.norm(traj.q[-1, position] - traj.q[k0, position]))
        out.update({"base_height_end": float(traj.q[-1, z]), "base_moved_end": moved,
                    "base_moved_window": float(traj.t[-1] - traj.t[k0])})
        print(f"the base ends at z = {traj.q[-1, z]:.6g} m and moved {moved:.2e} m in the last "
              f"{traj.t[-1] - traj.t[k0]:.3g} s")
    sunk = below_ground(model, traj.q[-1], scene.contacts.terrain.ground)
    out["below_ground_end"] = dict(sunk)
    if sunk:
        print(f"WARNING: at the end {len(sunk)} bodies are below the ground (only the contact points touch it): "
              + ", ".join(f"{name} at z = {h:.3g} m" for name, h in sunk[:6]) + (", ..." if len(sunk) > 6 else ""))
    return out


def free_fall_note(model: Model, base: str, duration: float, robot: bool = False) -> str:
    """The note for a model whose root is not welded to the world, simulated without the ground: it falls."""
    g = float(np.linalg.norm(np.asarray(model.gravity, dtype=float)))
    how = ("--no-ground: leave it out for the robot standing on the ground" if robot else
           "--ground with --contact LINK:x,y,z (points of its links) simulates it on the ground")
    return (f"note: this model has {base_words(base)} and no ground ({how}): the robot free-falls under gravity, about "
            f"{0.5 * g * duration ** 2:.3g} m in {duration:.3g} s")


def warn_missing_meshes(model: Model, package_dirs) -> None:
    """One line on stderr naming the meshes that --package-dir, ROS_PACKAGE_PATH and the installed
    example-robot-data do not hold (they are drawn as simple shapes), before a long render."""
    from .vis.geometry import MeshNotFoundWarning, model_shapes
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", MeshNotFoundWarning)
        model_shapes(model, package_dirs)
    for w in caught:
        if issubclass(w.category, MeshNotFoundWarning):
            print(f"hovi: warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def write_animation(model: Model, traj, args, ground: Optional[float] = None, terrain=None, arrows=None) -> None:
    """animation.html (meshcat, standalone) and animation.mp4 (offline render, with a progress bar on
    a terminal unless --no-progress) in args.output; ``ground``: the height of a ground grid (a
    floating or planar base), None for none; ``terrain`` (a hovi.contact.Terrain) its ground, gaps
    and boxes instead; ``arrows`` (hovi.vis.video.ForceArrows): contact forces as arrows; the
    pushes of ``--push`` (args.push) as arrows while they act."""
    pushes = getattr(args, "push", None) or None
    from .vis.geometry import MeshNotFoundWarning
    from .vis.video import render_video
    from .vis.viewer import animation_html

    warn_missing_meshes(model, args.package_dir)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshNotFoundWarning)  # said once above
        html = animation_html(model, traj, os.path.join(args.output, "animation.html"), fps=args.fps,
                              package_dirs=args.package_dir, ground=ground, terrain=terrain, arrows=arrows,
                              pushes=pushes)
        print(f"wrote {html} (open it in a browser: play, pause and scrub under Open Controls > Animations)")
        t0 = time.perf_counter()
        video = render_video(model, traj, os.path.join(args.output, "animation.mp4"), fps=args.fps,
                             package_dirs=args.package_dir, ground=ground, terrain=terrain, arrows=arrows,
                             pushes=pushes, progress=False if getattr(args, "no_progress", False) else None)
    print(f"wrote {video} ({time.perf_counter() - t0:.1f} s to render)")


#: Seconds between the heartbeat lines of a long solve (Heartbeat).
HEARTBEAT_SECONDS = 10.0


class Heartbeat:
    """Within a ``with`` block, while IPOPT runs, a line on stderr every ``every`` seconds: the time
    so far, the IPOPT iterations so far (of every solve of a contact homotopy) and the last one's
    primal infeasibility; also with --quiet, so that a solve of minutes is never silent. From the
    IPOPT adapter's iteration hook (``hovi.trajopt.solvers.ipopt.on_iteration``, ``solving``)."""

    def __init__(self, label: str, every: Optional[float] = None, stream=None, enabled: bool = True) -> None:
        self.label, self.every, self.enabled = label, HEARTBEAT_SECONDS if every is None else float(every), enabled
        self.stream = sys.stderr if stream is None else stream
        self.iterations, self.infeasibility = 0, float("nan")
        self._stop = threading.Event()
        self._thread: Optional[threading.Thread] = None
        self._hook = None

    def iteration(self, k: int, cost: float, inf_pr: float, inf_du: float) -> None:
        if k > 0:  # IPOPT reports its starting point as iteration 0 of each solve
            self.iterations += 1
        self.infeasibility = inf_pr

    def _beat(self) -> None:
        from .trajopt.solvers.ipopt import solving
        while not self._stop.wait(self.every):
            if not solving():  # between solves, or writing the files and the video (its own progress bar)
                continue
            print(f"{self.label}: {time.perf_counter() - self._start:.0f} s, {self.iterations} IPOPT iterations so far "
                  f"(primal infeasibility {self.infeasibility:.1e})", file=self.stream, flush=True)

    def __enter__(self) -> "Heartbeat":
        from .trajopt.solvers.ipopt import on_iteration
        self._hook = on_iteration(self.iteration)
        self._hook.__enter__()
        self._start = time.perf_counter()
        if self.enabled:
            self._thread = threading.Thread(target=self._beat, name="hovi-heartbeat", daemon=True)
            self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        if self._hook is not None:
            self._hook.__exit__(*exc)


def cmd_info(args) -> int:
    model = load_model(args.model, args.base)
    print(model.summary(), end="")
    rng = np.random.default_rng(args.seed)
    q = model.integrate(model.neutral(), rng.uniform(-np.pi / 2, np.pi / 2, model.n))
    qd = rng.uniform(-1, 1, model.n)
    K, V = model.kinetic_energy(q, qd), model.potential_energy(q)
    print(f"random state (seed {args.seed}): K = {K:.6g} J, V = {V:.6g} J, E = {K + V:.6g} J")
    return 0


def cmd_optimize(args) -> int:
    from . import trajopt
    from .trajopt.transcriptions import from_name
    make = get(OPTIMIZATION, args.example).function
    kwargs = {"controls": args.controls}
    if args.N is not None:
        kwargs["N"] = args.N
    if args.T is not None:
        kwargs["T"] = args.T
    prob = make(**kwargs)
    s = args.s
    label = f"VI s = {s} (order {2 * s})" if args.transcription == "vi" else args.transcription
    print(f"{args.example}: {prob.model.n} DoF, {prob.model.n_controls} controls, {prob.model.n_constraints} "
          f"constraint equations; N = {prob.N} stages over T = {prob.T} s; {label}")
    guess = "linear" if args.example == "acrobot" else None
    with Heartbeat(f"solving {args.example}", enabled=args.quiet):
        result = trajopt.solve(prob, from_name(args.transcription, s), guess=guess, verbose=not args.quiet,
                               options={"max_iter": args.max_iter})
    summary = {"example": args.example, "transcription": args.transcription, "s": args.s, "N": prob.N,
               "T": prob.T, "status": result.status, "success": result.success, "cost": result.cost,
               "constraint_violation": result.constraint_violation, "iterations": result.iterations,
               "wall_seconds": result.wall_seconds, **result.sizes, **{f"time_{k}": v for k, v in result.timing.items()}}
    if args.transcription == "vi":
        replay = result.replay()
        if replay.steps == prob.N:
            summary["replay_max_error"] = float(np.abs(replay.configuration_points - result.trajectory["q"]).max())
            print(f"replayed with the integrator: largest difference from the optimised states "
                  f"{summary['replay_max_error']:.2e}")
    print(f"{result.status}\ncost {result.cost:.8g}, constraint violation {result.constraint_violation:.2e}, "
          f"{result.iterations} iterations in {result.wall_seconds:.2f} s ({1e3 * result.timing['per_iteration']:.2f} "
          f"ms each; {100 * result.timing['callbacks'] / result.wall_seconds:.0f}% in hovi's callbacks)")
    if not result.success:
        worst = most_violated(result)
        summary["most_violated"] = worst
        print(f"NOT solved ({result.status.rstrip('.')}): the largest violation, {worst['violation']:.3g}, is {worst['what']}; "
              f"{worst['relax']}", file=sys.stderr)
    os.makedirs(args.output, exist_ok=True)
    traj, how = optimized_trajectory(result, prob, args.s)
    npz = os.path.join(args.output, f"optimize_{args.example}.npz")
    traj.save(npz)
    summary["trajectory_file"] = npz
    with open(os.path.join(args.output, f"optimize_{args.example}.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(f"wrote {npz} ({how}; hovi.load_trajectory reads it with Integrator(model, s={traj.control_points.shape[1] - 1}, "
          f"dt={prob.T / prob.N:g}))")
    if not args.no_plot:
        from .vis.plots import plot_optimized
        path = os.path.join(args.output, f"optimize_{args.example}.png")
        plot_optimized(result, prob, path, f"{args.example}, {label}, N = {prob.N}")
        print(f"wrote {path} and optimize_{args.example}.json")
    if args.animate:
        write_animation(prob.model, traj, args)
    return 0 if result.success else 1


def optimized_trajectory(result, prob, s: int):
    """The optimised motion as a hovi Trajectory (``save``/``load_trajectory``) and how it was made:
    a VI solution's own states and control points (status 'optimized', no Newton iterations);
    a Hermite-Simpson solution's controls replayed with the Galerkin VI of order 2s on its N stages."""
    from .trajopt.variational import VariationalTranscription
    tr = result.transcription
    if isinstance(tr, VariationalTranscription):
        return tr.solution_trajectory(result.x), "the optimised states of the VI transcription"
    integ = Integrator(prob.model, s=s, dt=prob.T / prob.N)
    q_of_t, v_of_t, u_of_t = result.as_guess()
    t = (np.arange(prob.N)[:, None] + integ.nodes[None, :]) * integ.dt
    u = None
    if prob.model.n_controls:
        u = np.asarray(u_of_t(t.ravel())).reshape(prob.N, integ.s + 1, prob.model.n_controls)
    traj = integ.rollout(np.asarray(q_of_t(np.zeros(1)))[0], prob.N, qdot0=np.asarray(v_of_t(np.zeros(1)))[0], u=u,
                         raise_on_failure=False)
    return traj, (f"the optimised controls replayed with the order-{integ.order} VI: {traj.steps} of {prob.N} steps; "
                  f"the Hermite-Simpson states are not a VI trajectory")


def most_violated(result) -> dict:
    """The constraint row or variable bound violated most at the solution: its kind (dynamics,
    path constraint, contact, boundary, input constraint, bound on q / p / v / u), where, by how much
    and what to relax."""
    from .trajopt.nlp import NLP
    tr = result.transcription
    nlp = NLP(tr)
    x = result.x
    g = nlp.constraints(x)
    rows = np.maximum(nlp.cl - g, g - nlp.cu)
    bounds = np.maximum(nlp.lower - x, x - nlp.upper)
    r, b = int(np.argmax(rows)) if len(rows) else -1, int(np.argmax(bounds))
    N, T = tr.problem.N, tr.problem.T
    if r >= 0 and rows[r] >= bounds[b]:
        kinds = [("the dynamics (the discrete equations of motion)", nlp.core.n_constraints,
                  "more stages (--N), more iterations (--max-iter), or a longer final time (--T)")]
        for c, _t, points, _w in nlp.paths:
            kinds.append((f"the path constraint {getattr(c, 'name', None) or type(c).__name__}",
                          points.shape[0] * len(c.lower), "relax that path constraint or give a longer --T"))
        if nlp.contact_rows is not None:
            kinds.append(("a contact condition", nlp.contact_rows.count, "a larger complementarity relaxation"))
        n_eq = tr.linear_rows()[0].shape[0]
        kinds.append(("a boundary condition", n_eq, "relax the boundary conditions or give a longer --T"))
        kinds.append(("an input constraint", len(nlp.cl) - sum(k[1] for k in kinds), "relax the input constraints"))
        start = 0
        for what, count, relax in kinds:
            if r < start + count:
                where = ""
                if what.startswith("the dynamics") and count % N == 0:
                    k = (r - start) // (count // N)
                    where = f" of stage {k} (t = {k * T / N:.3g}..{(k + 1) * T / N:.3g} s)"
                return {"violation": float(rows[r]), "what": what + where, "relax": relax, "row": r}
            start += count
    name, _, _ = tr.locate_variable(b)
    fixed = nlp.lower[b] == nlp.upper[b]
    relax = ("a boundary state is fixed there: relax the boundary conditions or give a longer --T" if fixed else
             "widen the control limits or give a longer --T" if name == "u" else
             "widen the joint limits or give a longer --T")
    return {"violation": float(bounds[b]),
            "what": f"the bound on {tr.describe_variable(b)}" + (" (a fixed boundary value)" if fixed else ""),
            "relax": relax, "variable": b}


def cmd_example(args) -> int:
    from .examples.paper import report
    if (args.push or args.mass_scale != 1.0) and not args.closed_loop:
        raise ValueError("argument --push/--mass-scale: they act on the closed loop; add --closed-loop")
    if len(args.push) > 1:
        raise ValueError("argument --push: the closed loop takes one push")
    if args.closed_loop and (args.transcription != "vi" or args.s != 1):
        raise ValueError("argument --closed-loop: the motion is tracked in the contact simulator, whose time-stepping "
                         "is the VI with s = 1 (leave out --transcription and -s)")
    example = get(ROBOT_EXAMPLE, args.name).build(quick=args.quick)
    prob = example.problem
    print(f"{args.name}: {example.description}; {prob.model.n} DoF, {prob.model.n_controls} inputs, N = {prob.N} "
          f"stages over T = {prob.T} s{' (quick)' if args.quick else ''}")
    with Heartbeat(f"solving {args.name}", enabled=not args.no_progress):
        s = report.run(example, args.output, animation=not args.no_animate, fps=args.fps, verbose=not args.quiet,
                       method=args.transcription, s=args.s, checkpoint=args.checkpoint,
                       progress=False if args.no_progress else None, closed_loop=args.closed_loop,
                       push=args.push[0] if args.push else None, mass_scale=args.mass_scale)
    print(f"{s['status']}: {s['iterations']} IPOPT iterations, {s['solve_seconds']:.1f} s; constraint violation "
          f"{s['constraint_violation']:.2e}")
    for key in example.bounds:
        print(f"  {key}: {s[key]:.3g}")
    if "replay_stage_residual" in s:
        print_replay(s)
    for line in s.get("report", []):     # between-knot penetration and the replay per stage, in words
        print(line)
    print("wrote " + ", ".join(s["files"]))
    if not s["feasible"]:
        print("NOT feasible: " + "; ".join(s["failures"]), file=sys.stderr)
    tracked = s.get("closed_loop", {}).get("closed_loop", {}).get("success", True)
    if not tracked:
        print("the closed loop FAILED: it did not reach the example's goal (see the line above)", file=sys.stderr)
    return 0 if s["feasible"] and tracked else 1


def print_replay(s) -> None:
    """The replay figures of a VI solution (report.replay_figures)."""
    print(f"checked with the integrator: the stages' DEL residual {s['replay_stage_residual']:.2e}; a step from each "
          f"optimised state lands {s['replay_one_step_drift']:.2e} from the next ({s['replay_steps_elsewhere']} more than 1e-6 "
          f"away: with a small residual, another root of the DEL equations; {s['replay_failed_steps']} failed); the whole horizon open loop drifts "
          f"{s['replay_open_loop_drift']:.2e}")
    print(f"energy along the motion: {s['energy_start']:.6g} -> {s['energy_end']:.6g} J (range {s['energy_min']:.6g} "
          f".. {s['energy_max']:.6g})")


def number(kind, condition: str):
    """An argparse type: ``kind`` (int or float) that is finite and satisfies ``condition``
    ('> 0', '>= 0', '>= 1' or '>= 2'); argparse names the flag in its message."""
    bound = float(condition.split()[1])
    strict = condition.startswith(">") and not condition.startswith(">=")

    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"'{text}' is not {'a whole number' if kind is int else 'a number'}") from None
        if not np.isfinite(value) or (value <= bound if strict else value < bound):
            raise argparse.ArgumentTypeError(f"must be {'a whole number' if kind is int else 'a finite number'} "
                                             f"{condition}, got '{text}'")
        return value
    parse.__name__ = "whole number" if kind is int else "number"
    return parse


positive = number(float, "> 0")
non_negative = number(float, ">= 0")
count = number(int, ">= 1")
seed = number(int, ">= 0")


def finite(text: str) -> float:
    """An argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number") from None
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got '{text}'")
    return value


def friction(text: str) -> float:
    """An argparse type: a friction coefficient, a finite number >= 0 and at most MAX_FRICTION."""
    from .contact.contacts import MAX_FRICTION
    value = non_negative(text)
    if value > MAX_FRICTION:
        raise argparse.ArgumentTypeError(f"must be a friction coefficient from 0 to {MAX_FRICTION:g} (real ones are "
                                         f"below about 2), got '{text}'")
    return value


def contact_point(text: str) -> Tuple[str, Tuple[float, float, float]]:
    """An argparse type: LINK:x,y,z (a point of a link, in the link's frame, m), or LINK (its origin)."""
    link, colon, xyz = text.rpartition(":")
    if not colon:
        link, xyz = text, "0,0,0"
    shape = ("is not LINK:x,y,z (a link's name, a colon and 3 numbers: the point in the link's frame, in m), "
             "e.g. foot:0,0,-0.05")
    parts = xyz.split(",")
    if not link.strip() or len(parts) != 3:
        raise argparse.ArgumentTypeError(f"'{text}' {shape}")
    try:
        point = tuple(float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' {shape}") from None
    if not all(np.isfinite(point)):
        raise argparse.ArgumentTypeError(f"'{text}': the point must be 3 finite numbers")
    return link.strip(), point  # type: ignore[return-value]


def push(text: str):
    """An argparse type: BODY:t,ix,iy,iz (an impulse of ix, iy, iz N s on the body's origin at time t s)
    or BODY:t,ix,iy,iz,ax,ay,az (a wrench impulse: and the angular impulse ax, ay, az N m s), a
    ``hovi.control.Push``."""
    from .control import Push
    body, colon, numbers = text.rpartition(":")
    shape = ("is not BODY:t,ix,iy,iz (a body's name, a colon, the time in s and the impulse in N s) or "
             "BODY:t,ix,iy,iz,ax,ay,az (and the angular impulse in N m s), e.g. body:1.0,2,0,0")
    parts = numbers.split(",")
    if not colon or not body.strip() or len(parts) not in (4, 7):
        raise argparse.ArgumentTypeError(f"'{text}' {shape}")
    try:
        values = [float(x) for x in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' {shape}") from None
    if not all(np.isfinite(values)) or values[0] < 0:
        raise argparse.ArgumentTypeError(f"'{text}': the time must be >= 0 and every number finite")
    return Push(values[0], body.strip(), values[1:4], angular=values[4:7] if len(values) == 7 else (0.0, 0.0, 0.0))


def add_model_args(p):
    p.add_argument("model", nargs="?", default="pendulum:32", help=model_listing() + " (default: pendulum:32)")
    p.add_argument("--base", default=None, choices=["fixed", "floating", "euler", "planar"],
                   help="how a URDF's root link is attached to the world (default: fixed)")
    p.add_argument("--seed", type=seed, default=0, help="seed of the random initial state (default: 0)")


def add_animation_arguments(parser: argparse.ArgumentParser) -> None:
    """--animate, --fps and --package-dir: the same for every command that animates its motion."""
    parser.add_argument("--animate", action="store_true",
                        help="also write animation.html (3D view, opens without a server) and animation.mp4 "
                             "(needs hovi[viewer]: meshcat, imageio-ffmpeg, trimesh)")
    parser.add_argument("--fps", type=positive, default=20.0, help="frames per second of the animation (default: 20)")
    parser.add_argument("--package-dir", action="append", default=[], metavar="DIR",
                        help="directory searched for package:// meshes (repeatable; then ROS_PACKAGE_PATH)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="hovi", description="Higher-order variational integrators for robots.")
    parser.add_argument("--version", action="version", version=f"hovi {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    sim = sub.add_parser("simulate", help="simulate a model and report speed and energy error (robots: on the ground)",
                         description="Simulate from a random configuration at rest with the Galerkin variational "
                                     "integrator; print steps per second, Newton iterations per step and the "
                                     "energy error; write plots and a JSON summary. The built-in robots "
                                     f"({', '.join(STANDING)}) stand on the ground by default: dropped from a few cm, "
                                     "they land and stand (joint PD and feed-forward torques; hard contact with "
                                     "friction, s = 1); the summary gives the landing time, the deepest "
                                     "penetration and the contact force against the weight. Any other model goes on "
                                     "the ground with --ground and its contact points (--contact).")
    add_model_args(sim)
    sim.add_argument("-s", type=count, default=None, metavar="S",
                     help="Lobatto intervals per step, the order of accuracy being 2s: 1 trapezoidal, 2 Simpson, 3, 4, "
                          "... up to 16 (default: 2; on the ground 1)")
    sim.add_argument("--dt", type=positive, default=None,
                     help=f"time step in seconds (default: 0.01; on the ground {GROUND_DT})")
    sim.add_argument("--duration", type=positive, default=10.0, help="simulated time in seconds (default: 10)")
    sim.add_argument("--spread", type=non_negative, default=None,
                     help="initial joint positions uniform in [-spread, spread] rad or m (default: pi/12, the "
                          "paper's Fig. 4 range; larger values make a long chain whip and need a smaller dt); a "
                          "built-in robot on the ground: offsets from its standing pose (default: 0)")
    ground = sim.add_mutually_exclusive_group()
    ground.add_argument("--ground", dest="ground", action="store_true", default=None,
                        help="simulate on the ground with hard contact and Coulomb friction (the default for the "
                             f"built-in robots {', '.join(STANDING)}; other models need --contact)")
    ground.add_argument("--no-ground", dest="ground", action="store_false",
                        help="no ground (for a built-in robot too): a floating or planar base free-falls, as "
                             "before hovi had contact")
    sim.add_argument("--contact", type=contact_point, action="append", default=[], metavar="LINK:x,y,z",
                     help="a contact point of a link, in the link's frame (m) (repeatable; implies --ground): e.g. "
                          "--contact foot:0,0,-0.05; the built-in robots have theirs")
    sim.add_argument("--mu", type=friction, default=None,
                     help=f"friction coefficient of the ground (default: {DEFAULT_FRICTION:g}; implies --ground)")
    sim.add_argument("--drop", type=non_negative, default=DROP,
                     help=f"on the ground, the lowest contact point starts this high above it, m (default: {DROP:g}); "
                          "a fixed base is not moved")
    sim.add_argument("--push", type=push, action="append", default=[], metavar="BODY:t,ix,iy,iz",
                     help="push a body: an impulse (N s, world axes) on its origin at time t (s), or a wrench "
                          "impulse BODY:t,ix,iy,iz,ax,ay,az (and an angular impulse, N m s) (repeatable), e.g. "
                          "--push body:1.0,0.5,0,0; drawn in the pictures and the animation")
    sim.add_argument("--ground-height", type=finite, default=0.0,
                     help="height of the ground plane, m (default: 0)")
    sim.add_argument("--tol", type=non_negative, default=0.0,
                     help="optional residual tolerance ||r|| <= tol (1 + ||p||) (default 0: converge to round-off)")
    sim.add_argument("--output", default="results", help="folder for the plots and JSON (default: results)")
    sim.add_argument("--no-plot", action="store_true", help="skip the plots")
    sim.add_argument("--no-progress", action="store_true", help="no progress bar")
    add_animation_arguments(sim)
    sim.set_defaults(func=cmd_simulate)
    opt = sub.add_parser("optimize", help="solve a built-in trajectory optimisation with IPOPT",
                         description="Solve a built-in trajectory-optimisation example (swing-ups with torque "
                                     "limits and a fixed final time; a slider-crank driven to a target) with the "
                                     "variational integrator or Hermite-Simpson collocation as the dynamics; print "
                                     "IPOPT's progress and a summary; replay the optimised controls with the "
                                     "integrator; write the trajectory (npz, hovi.load_trajectory), a plot and a "
                                     "JSON summary; a solve that fails names the constraint or bound violated most.")
    opt.add_argument("example", choices=names(OPTIMIZATION),
                     help="the example: " + "; ".join(f"{e.name}: {e.description}" for e in entries(OPTIMIZATION).values()))
    opt.add_argument("--transcription", default="vi", choices=["vi", "hs-implicit", "hs-explicit"],
                     help="the dynamics: the Galerkin VI (default) or Hermite-Simpson collocation")
    opt.add_argument("-s", type=count, default=2, metavar="S",
                     help="the VI's Lobatto intervals per stage, order 2s (default 2: Simpson)")
    opt.add_argument("--N", type=count, default=None, help="number of stages, >= 1 (default: the example's)")
    opt.add_argument("--T", type=positive, default=None, help="final time in s, > 0 (default: the example's)")
    opt.add_argument("--controls", default="per_point", choices=["per_point", "held"],
                     help="controls at every sample point (default) or held over each stage")
    opt.add_argument("--max-iter", type=count, default=3000, help="IPOPT iteration limit (default 3000)")
    opt.add_argument("--quiet", action="store_true", help="no per-iteration progress (a line every 10 s instead)")
    opt.add_argument("--no-progress", action="store_true", help="no progress bar while the video renders")
    opt.add_argument("--output", default="results", help="folder for the trajectory, plot and JSON (default: results)")
    opt.add_argument("--no-plot", action="store_true", help="skip the plot")
    add_animation_arguments(opt)
    opt.set_defaults(func=cmd_optimize)
    ROBOT_EXAMPLES = names(ROBOT_EXAMPLE)
    ex = sub.add_parser("example", help="the paper's robot examples (Sec. 6): " + ", ".join(ROBOT_EXAMPLES),
                        description="Solve one of the paper's robot trajectory optimisations with the variational "
                                    "integrator (or Hermite-Simpson collocation); print IPOPT's progress, the solve time, the feasibility figures and "
                                    "the drift when the optimised controls are replayed; write the trajectory (npz), "
                                    "a JSON summary, a plot and an animation (HTML and MP4).")
    ex.add_argument("name", choices=ROBOT_EXAMPLES, help="the example: " + "; ".join(
        f"{e.name}: {e.description}" for e in entries(ROBOT_EXAMPLE).values()))
    ex.add_argument("--quick", action="store_true", help="a short horizon (what the tests run)")
    ex.add_argument("--transcription", default="vi", choices=["vi", "hs-implicit", "hs-explicit"],
                    help="the dynamics: the Galerkin VI (default) or Hermite-Simpson collocation with the same "
                         "contact conditions")
    ex.add_argument("-s", type=int, default=1, choices=[1, 2, 3, 4], metavar="S",
                    help="the VI's Lobatto intervals per stage, order 2s (default 1: the trapezoidal VI, inelastic "
                         "impacts; 2: the paper's Simpson VI)")
    ex.add_argument("--output", default="results", help="directory for the files (default: results)")
    ex.add_argument("--no-animate", action="store_true", help="skip the animation (needs hovi[viewer])")
    ex.add_argument("--fps", type=positive, default=25.0, help="frames per second of the animation (default: 25)")
    ex.add_argument("--quiet", action="store_true", help="no IPOPT progress lines (a line every 10 s still says "
                                                         "how far the solve is)")
    ex.add_argument("--no-progress", action="store_true", help="no line every 10 s during the solve and no progress "
                                                              "bar while the video renders")
    ex.add_argument("--closed-loop", action="store_true",
                    help="then track the optimised motion by time-varying LQR in the contact simulator and say "
                         "whether it reaches the example's goal (VI, s = 1)")
    ex.add_argument("--push", type=push, action="append", default=[], metavar="BODY:t,ix,iy,iz",
                    help="with --closed-loop: push a body (an impulse in N s at time t in s; ,ax,ay,az adds an "
                         "angular impulse in N m s), e.g. body:0.6,0.2,0,0")
    ex.add_argument("--mass-scale", type=positive, default=1.0, metavar="F",
                    help="with --closed-loop: every body's mass and inertia times F in the plant (default 1)")
    ex.add_argument("--checkpoint", default=None, metavar="FILE",
                    help="keep the contact homotopy's state in FILE (npz) after each relaxed solve and resume from it "
                         "if it exists: a solve of hours survives an interruption")
    ex.set_defaults(func=cmd_example)
    info = sub.add_parser("info", help="describe a model and print its energy at a random state")
    add_model_args(info)
    info.set_defaults(func=cmd_info)
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, OSError) as e:  # bad model file, bad option value: a clean message, no traceback
        print(f"hovi: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
