"""Deprecated module (one release): the contact homotopy moved to
``hovi.trajopt.solvers.contact_homotopy`` (``ContactHomotopy``, ``solve_contact``), the reading of
the pairs' sides to ``hovi.contact.sides``."""
from __future__ import annotations

import warnings

from ..contact import sides as sides_module
from .solvers import contact_homotopy as homotopy_module

MOVED = {"solve_contact": (homotopy_module, "hovi.trajopt.solve_contact"),
         "DEFAULT_EPSILONS": (homotopy_module, "hovi.trajopt.solvers.contact_homotopy.DEFAULT_EPSILONS"),
         "FINISH_BELOW": (homotopy_module, "hovi.trajopt.solvers.contact_homotopy.FINISH_BELOW"),
         "RELAXED_TOL": (homotopy_module, "hovi.trajopt.solvers.contact_homotopy.RELAXED_TOL"),
         "canonical": (sides_module, "hovi.contact.canonical"),
         "branches_of": (sides_module, "hovi.contact.branches_of"),
         "least_slack": (sides_module, "hovi.contact.least_slack")}


def __getattr__(name: str):
    if name in MOVED:
        module, new = MOVED[name]
        warnings.warn(f"hovi.trajopt.contact_solve.{name} is deprecated: use {new}", DeprecationWarning,
                      stacklevel=2)
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
