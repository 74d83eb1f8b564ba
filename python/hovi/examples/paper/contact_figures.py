"""The feasibility figures of a contact-implicit solution (``hovi.trajopt.solve_contact``), computed
from the trajectory itself rather than read from the solver's rows: the deepest penetration of a
contact point at any configuration point, and the largest normal complementarity product
lambda_i phi(q_{i+1}) (the pairing of ``hovi.contact.contacts``); beside them the solver's own
largest product over all pairs (normal, cone and sliding) and whether its exact solve finished.
``path_configurations``: the configurations along the whole solution, for obstacle checks that
must hold between the configuration points too.

Between the configuration points a contact point follows the transcription's own polynomial
(``Transcription.q_samples``), where no contact row holds it: ``between_knot_penetration`` samples
it densely (at least BETWEEN_MIN_SAMPLES times between each two points and every BETWEEN_SPACING)
and reports the deepest dip below the terrain, the contact and the time; a solution is feasible
only if it is at most BETWEEN_TOLERANCE (checking the knots alone called feasible a Spring Flamingo
whose feet dipped tens of millimetres between them: bench/README.md, "What the checks see between
the points")."""
from __future__ import annotations

from typing import Any, Callable, Dict, Optional, Sequence, Tuple

import numpy as np

from ...contact import Contacts
from ...trajopt import Result

BETWEEN_TOLERANCE = 1e-3     # m: the deepest a contact point may dip below the terrain between the points
BETWEEN_SPACING = 0.0025     # s: the samples between two configuration points are at most this far apart
BETWEEN_MIN_SAMPLES = 19     # and at least this many between each two (20 intervals)


def between_samples(result: Result, spacing: float = BETWEEN_SPACING,
                    least: int = BETWEEN_MIN_SAMPLES) -> Tuple[np.ndarray, np.ndarray]:
    """(t (K,), q (K, n)): the configurations strictly between the solution's configuration points,
    on its transcription's polynomial (``Transcription.q_samples``: weighted sums of the stage's
    points), at least ``least`` between each two and at most ``spacing`` s apart."""
    tc = result.transcription
    t_points = result.trajectory["t"]
    h = float(np.max(np.diff(t_points)))
    between = max(int(least), int(np.ceil(h / spacing - 1e-9)) - 1)
    t, points, weights = tc.q_samples(between)
    q = result.trajectory["q"]
    return t, np.einsum("pk,pkn->pn", weights, q[points])


def between_knot_penetration(result: Result, gaps: Callable[[np.ndarray], np.ndarray], names: Sequence[str],
                             spacing: float = BETWEEN_SPACING, least: int = BETWEEN_MIN_SAMPLES) -> Dict[str, Any]:
    """The worst dip of a contact point below the terrain between the configuration points:
    {'between_knot_penetration' (m, >= 0), 'between_knot_contact' (its name), 'between_knot_time'
    (s)}; ``gaps(q (K, n)) -> (K, C)`` the signed gaps (negative: below the terrain) of the contacts
    ``names`` (C,), sampled as ``between_samples``. With no dip, the contact and time of the
    smallest gap."""
    t, q = between_samples(result, spacing, least)
    phi = np.asarray(gaps(q), float).reshape(len(t), len(names))
    k, c = np.unravel_index(int(np.argmin(phi)), phi.shape)
    return {"between_knot_penetration": float(max(0.0, -phi[k, c])), "between_knot_contact": str(names[c]),
            "between_knot_time": float(t[k])}


def contact_gaps(contacts: Contacts) -> Callable[[np.ndarray], np.ndarray]:
    """gaps(q (K, n)) -> (K, C): the signed gaps of ``contacts`` to its terrain, batched."""
    core = contacts.core_model()

    def gaps(q: np.ndarray) -> np.ndarray:
        phi: np.ndarray = core.gaps(contacts.positions(np.atleast_2d(q)))
        return phi
    return gaps


def between_knot_text(figures: Dict[str, Any]) -> str:
    """The between-knot figure in words with units."""
    depth, where = figures["between_knot_penetration"], (f"{figures['between_knot_contact']} at "
                                                        f"t = {figures['between_knot_time']:.3f} s")
    if depth > 0:
        verdict = "within" if depth <= BETWEEN_TOLERANCE else "beyond"
        return (f"between the configuration points: worst penetration {depth * 1e3:.3g} mm ({where}), {verdict} the "
                f"{BETWEEN_TOLERANCE * 1e3:g} mm tolerance")
    return f"between the configuration points: no contact point below the terrain (nearest: {where})"


def contact_figures(contacts: Contacts, result: Result, names: Optional[Sequence[str]] = None) -> Dict[str, Any]:
    """{'penetration', 'normal_complementarity', 'complementarity', 'exact_solve'} of ``result``, a
    VI solution with controls at every control point (the configuration points of the contact
    conditions: the trajectory's points), and the between-knot figures of
    ``between_knot_penetration`` (the contacts named ``names``, default 'contact c')."""
    tr = result.trajectory
    if len(tr["q"]) != len(tr["u"]):
        raise ValueError("the contact figures need controls at every configuration point (controls='per_point')")
    phi = np.array([contacts.gaps(q) for q in tr["q"]])                     # (P, C)
    lam = tr["u"][:, [contacts.input_index(c, "normal") for c in range(contacts.n_contacts)]]
    return {"penetration": float(max(0.0, -phi.min())),
            "normal_complementarity": float(np.abs(lam[:-1] * phi[1:]).max()),
            "complementarity": float(result.contact["complementarity"]),
            "exact_solve": float(result.contact["finished"]),
            **between_knot_penetration(result, contact_gaps(contacts),
                                       names or [f"contact {c}" for c in range(contacts.n_contacts)])}


def path_configurations(result: Result, between: int = 200) -> np.ndarray:
    """The configurations (P, n) of the solution at its configuration points and at ``between``
    evenly spaced times between each two, on the transcription's polynomial."""
    tr = result.transcription
    return np.vstack([result.trajectory["q"], tr.interpolants(result.x)[0](tr.q_samples(between)[0])])


CONTACT_BOUNDS = {"penetration": ("<=", 1e-6), "normal_complementarity": ("<=", 1e-6),
                  "complementarity": ("<=", 1e-6), "exact_solve": (">=", 1.0),
                  "between_knot_penetration": ("<=", BETWEEN_TOLERANCE)}
