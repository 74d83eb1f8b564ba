"""The optimised motion of a robot example executed in the contact simulator: the robot's
own model with the example's contacts (``Example.simulation``) stepped by ``hovi.Integrator(...,
contacts=...)`` from the optimised initial state with the optimised joint torques, open loop (the
contact forces are the simulator's, not the optimiser's). How far it follows the optimised
configurations, whether it makes and breaks contact where the optimiser did, and where it departs.

The optimiser's VI (s = 1) with its contact forces at the knots is the contact step of the
simulator with the same dt (the impulse at a knot, (w^0 + w^s) dt times the knot force, decides the
next knot): a solution whose complementarity holds exactly is a trajectory of the simulator, up to
the LCP's choice among equal-motion force distributions (redundant contacts) and the growth of
round-off along an open-loop, unstable motion (a balancing robot has no feedback)."""
from __future__ import annotations

from typing import Any, Dict

import numpy as np

from ...integrator import Integrator
from ...trajopt import Result
from .example import Example

DEPARTED = 1e-3   # m or rad: the simulated motion has departed from the optimised one beyond this
ACTIVE = 1e-6     # N: a contact force above this (optimiser) or a normal impulse above 0 (simulator) is contact


def simulated_figures(example: Example, result: Result) -> Dict[str, Any]:
    """{'sim_steps', 'sim_status', 'sim_min_gap' (m, the deepest point at the knots), 'sim_max_deviation'
    (m or rad, over the horizon), 'sim_departs_at' (s: first knot beyond DEPARTED, or None),
    'sim_departs_joint', 'sim_final_deviation', 'sim_contact_agreement' (fraction of (knot, contact)
    pairs where simulator and optimiser agree on contact, or None when the example's forces are not
    per contact point), 'sim_first_contact_difference' (s, contact name) or None}."""
    contacts = example.simulation
    if contacts is None:
        return {}
    tr, tc = result.trajectory, result.transcription
    prob, robot = example.problem, example.robot
    m = robot.model.n_controls
    U = tc.stage_controls(result.x)[:, :, :m]                  # (N, s+1, m): the robot's own torques
    integ = Integrator(robot.model, s=1, dt=prob.dt, contacts=contacts)
    knots = tr["q"][::tc.s]
    sim = integ.rollout(knots[0], len(knots) - 1, qdot0=prob.qdot0, u=U if m else None, raise_on_failure=False)
    K = sim.steps
    dev = np.abs(sim.q[:K + 1] - knots[:K + 1])
    per_knot = dev.max(axis=1)
    departed = np.flatnonzero(per_knot > DEPARTED)
    names = list(robot.model.joint_names)
    out: Dict[str, Any] = {
        "sim_steps": int(K), "sim_of_steps": int(len(knots) - 1), "sim_status": sim.status[-1] if sim.status else "converged",
        "sim_min_gap": float(sim.contact.gaps.min()) if K else 0.0,
        "sim_max_deviation": float(per_knot.max()), "sim_final_deviation": float(per_knot[-1]),
        "sim_departs_at": float(sim.t[departed[0]]) if departed.size else None,
        "sim_departs_joint": names[int(np.argmax(dev[departed[0]]))] if departed.size else None,
        "sim_contact_agreement": None, "sim_first_contact_difference": None}
    forces = example.contact_forces(tr["u"][::tc.s][:K])         # (K, labels): the optimiser's at the knots
    if forces.shape[1] == contacts.n_contacts and K:
        opt = forces > ACTIVE
        mine = sim.contact.normal[:K] > 0
        agree = opt == mine
        out["sim_contact_agreement"] = float(agree.mean())
        bad = np.argwhere(~agree)
        if bad.size:
            k, c = bad[0]
            out["sim_first_contact_difference"] = (float(sim.t[k]), example.force_labels[c])
    return out


def simulated_text(fig: Dict[str, Any]) -> str:
    """The execution in the contact simulator, in plain words with units."""
    if not fig:
        return "executed in the contact simulator: not available for this example"
    text = (f"executed open loop in the contact simulator: {fig['sim_steps']} of {fig['sim_of_steps']} steps "
            f"({fig['sim_status']}), deepest point {max(0.0, -fig['sim_min_gap']):.1e} m below the terrain; ")
    if fig["sim_departs_at"] is None:
        text += f"it follows the optimised motion to {fig['sim_max_deviation']:.1e} (m or rad)"
    else:
        text += (f"it departs from the optimised motion at t = {fig['sim_departs_at']:.3g} s ({fig['sim_departs_joint']} "
                 f"first beyond {DEPARTED:g}) and ends {fig['sim_final_deviation']:.3g} (m or rad) away")
    if fig["sim_contact_agreement"] is not None:
        text += f"; contact made and broken as optimised at {100 * fig['sim_contact_agreement']:.1f}% of knots and contacts"
        if fig["sim_first_contact_difference"] is not None:
            t, name = fig["sim_first_contact_difference"]
            text += f" (first difference: {name} at t = {t:.3g} s)"
    return text
