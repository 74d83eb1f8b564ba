"""The paper's Sec. 6 examples on its three robots (``hovi example NAME``): each module builds its
trajectory-optimisation problem (``build(quick)`` -> ``example.Example``), ``report.run`` solves,
checks, replays and writes it. Importing this package loads nothing heavy (the command line lists
NAMES without IPOPT or scipy)."""
from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .example import Example

NAMES = ("flamingo", "littledog", "atlas")

__all__ = ["NAMES", "build"]


def build(name: str, quick: bool = False) -> Example:
    """The example ``name`` (one of NAMES), full or ``quick`` (a short horizon)."""
    if name not in NAMES:
        raise ValueError(f"unknown example '{name}' (choose from {', '.join(NAMES)})")
    from importlib import import_module
    return import_module(f".{name}", __name__).build(quick=quick)
