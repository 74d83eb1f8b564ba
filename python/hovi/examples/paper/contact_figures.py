"""The feasibility figures of a contact-implicit solution (``hovi.trajopt.solve_contact``), computed
from the trajectory itself rather than read from the solver's rows: the deepest penetration of a
contact point at any configuration point, and the largest normal complementarity product
lambda_i phi(q_{i+1}) (the pairing of ``hovi.contact.contacts``); beside them the solver's own
largest product over all pairs (normal, cone and sliding) and whether its exact solve finished.
``path_configurations``: the configurations along the whole solution, for obstacle checks that
must hold between the configuration points too."""
from __future__ import annotations

from typing import Dict

import numpy as np

from ...contact import Contacts
from ...trajopt import Result


def contact_figures(contacts: Contacts, result: Result) -> Dict[str, float]:
    """{'penetration', 'normal_complementarity', 'complementarity', 'exact_solve'} of ``result``, a
    VI solution with controls at every control point (the configuration points of the contact
    conditions: the trajectory's points)."""
    tr = result.trajectory
    if len(tr["q"]) != len(tr["u"]):
        raise ValueError("the contact figures need controls at every configuration point (controls='per_point')")
    phi = np.array([contacts.gaps(q) for q in tr["q"]])                     # (P, C)
    lam = tr["u"][:, [contacts.input_index(c, "normal") for c in range(contacts.n_contacts)]]
    return {"penetration": float(max(0.0, -phi.min())),
            "normal_complementarity": float(np.abs(lam[:-1] * phi[1:]).max()),
            "complementarity": float(result.contact["complementarity"]),
            "exact_solve": float(result.contact["finished"])}


def path_configurations(result: Result, between: int = 200) -> np.ndarray:
    """The configurations (P, n) of the solution at its configuration points and at ``between``
    evenly spaced times between each two, on the transcription's polynomial."""
    tr = result.transcription
    return np.vstack([result.trajectory["q"], tr.interpolants(result.x)[0](tr.q_samples(between)[0])])


CONTACT_BOUNDS = {"penetration": ("<=", 1e-6), "normal_complementarity": ("<=", 1e-6),
                  "complementarity": ("<=", 1e-6), "exact_solve": (">=", 1.0)}
