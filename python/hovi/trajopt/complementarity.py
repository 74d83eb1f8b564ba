"""Deprecated module (one release): the contact complementarity rows moved to
``hovi.contact.complementarity`` (``hovi.contact.ContactRows``, ``Branches``)."""
from __future__ import annotations

import warnings

from ..contact import complementarity as complementarity_module


def __getattr__(name: str):
    if name in ("ContactRows", "Branches"):
        warnings.warn(f"hovi.trajopt.complementarity.{name} is deprecated: use hovi.contact.{name}",
                      DeprecationWarning, stacklevel=2)
        return getattr(complementarity_module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
