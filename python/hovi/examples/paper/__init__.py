"""The paper's Sec. 6 examples on its three robots (``hovi example NAME``): each module builds its
trajectory-optimisation problem (``build(quick)`` -> ``example.Example``), ``report.run`` solves,
checks, replays and writes it. Importing this package loads nothing heavy (the command line lists
NAMES without IPOPT or scipy); the names and descriptions are the registry's
(``hovi.examples.entries('robot_example')``)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from .. import ROBOT_EXAMPLE, get, names

if TYPE_CHECKING:
    from .example import Example

NAMES = names(ROBOT_EXAMPLE)

__all__ = ["NAMES", "build"]


def build(name: str, quick: bool = False) -> Example:
    """The example ``name`` (one of NAMES), full or ``quick`` (a short horizon)."""
    if name not in NAMES:
        raise ValueError(f"unknown example '{name}' (choose from {', '.join(NAMES)})")
    example: Example = get(ROBOT_EXAMPLE, name).build(quick=quick)
    return example
