"""The paper's Sec. 6 examples on its three robots (``hovi example NAME``): each module builds its
trajectory-optimisation problem (``build(quick)`` -> ``Example``), ``report.run`` solves, checks,
replays and writes it."""
from .example import Example, Scenery

NAMES = ("atlas",)

__all__ = ["Example", "Scenery", "NAMES", "build"]


def build(name: str, quick: bool = False) -> Example:
    """The example ``name`` (one of NAMES), full or ``quick`` (a short horizon)."""
    if name not in NAMES:
        raise ValueError(f"unknown example '{name}' (choose from {', '.join(NAMES)})")
    from importlib import import_module
    return import_module(f".{name}", __name__).build(quick=quick)
