"""Terrain for contact: a ground plane at height ``ground`` with gaps (strips where the ground is
missing) and boxes (raised blocks), all with horizontal top faces, so the surface normal is +z
wherever a foot can stand. The signed gap of a world point is its height above the surface below
it, phi(x) = z - h(x, y), with h piecewise constant (its gradient is (0, 0, 1) away from edges)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Sequence, Tuple

import numpy as np

from .. import _core
from .._checks import real_number


# Terrains, gaps and boxes are frozen: an integrator or a problem made with them keeps computing what
# it was made with, and so does every copy of it (a pickled one is made anew from them).
@dataclass(frozen=True)
class Gap:
    """No ground for x0 < x < x1 (a strip across y), down to ``depth`` below the ground (x0, x1 and
    depth finite numbers, x0 < x1, depth > 0)."""
    x0: float
    x1: float
    depth: float = 1.0

    def __post_init__(self) -> None:
        x0, x1 = real_number(self.x0, "Gap.x0"), real_number(self.x1, "Gap.x1")
        real_number(self.depth, "Gap.depth", minimum=0.0, strict_minimum=True)
        if not x0 < x1:
            raise ValueError(f"Gap needs x0 < x1, got x0 = {x0}, x1 = {x1}")


@dataclass(frozen=True)
class Box:
    """A block with its top face at height ``top`` over x0 < x < x1, y0 < y < y1 (x0, x1 and top
    finite numbers, y0 and y1 numbers, +-inf allowed)."""
    x0: float
    x1: float
    top: float
    y0: float = -np.inf
    y1: float = np.inf

    def __post_init__(self) -> None:
        x0, x1 = real_number(self.x0, "Box.x0"), real_number(self.x1, "Box.x1")
        y0, y1 = real_number(self.y0, "Box.y0", finite=False), real_number(self.y1, "Box.y1", finite=False)
        real_number(self.top, "Box.top")
        if not (x0 < x1 and y0 < y1):
            raise ValueError(f"Box needs x0 < x1 and y0 < y1, got x0 = {x0}, x1 = {x1}, y0 = {y0}, y1 = {y1}")


@dataclass(frozen=True)
class Terrain:
    """Flat ground at height ``ground`` with ``gaps`` and ``boxes`` (boxes stand above gaps); fixed
    once made (``dataclasses.replace(terrain, ground=0.1)`` makes a changed copy)."""
    ground: float = 0.0
    gaps: Sequence[Gap] = ()
    boxes: Sequence[Box] = ()

    def __post_init__(self) -> None:
        real_number(self.ground, "Terrain ground")
        for field_name, kind in (("gaps", Gap), ("boxes", Box)):
            items = getattr(self, field_name)
            if isinstance(items, (str, bytes, dict)) or not hasattr(items, "__iter__"):
                raise TypeError(f"Terrain {field_name} must be a list of hovi.contact.{kind.__name__}, got "
                                f"{type(items).__name__}")
            items = tuple(items)
            for i, item in enumerate(items):
                if not isinstance(item, kind):
                    raise TypeError(f"Terrain {field_name}[{i}] must be a hovi.contact.{kind.__name__}, got "
                                    f"{type(item).__name__} {item!r:.60}")
            object.__setattr__(self, field_name, items)

    def arrays(self) -> Tuple[float, np.ndarray, np.ndarray]:
        """(ground, gaps (G, 3) rows (x0, x1, depth), boxes (B, 5) rows (x0, x1, top, y0, y1)): the
        terrain as the C++ contact models read it."""
        gaps = np.array([[g.x0, g.x1, g.depth] for g in self.gaps], dtype=np.float64).reshape(-1, 3)
        boxes = np.array([[b.x0, b.x1, b.top, b.y0, b.y1] for b in self.boxes], dtype=np.float64).reshape(-1, 5)
        return float(self.ground), gaps, boxes

    def core(self) -> _core.Terrain:
        """This terrain as C++ holds it (the one home of its height: the contact stages and rows read it)."""
        return _core.Terrain(*self.arrays())

    def height(self, xy: np.ndarray) -> np.ndarray:
        """h (P,) of the surface below the points xy (P, 2), in C++."""
        heights: np.ndarray = self.core().heights(np.atleast_2d(xy))
        return heights

    def gap(self, points: np.ndarray) -> np.ndarray:
        """The signed gap phi (P,) of world points (P, 3): positive above the surface."""
        points = np.atleast_2d(points)
        return points[:, 2] - self.height(points[:, :2])

    def segments(self, x_range: Tuple[float, float]) -> List[Tuple[float, float, float]]:
        """(x0, x1, height) pieces of the surface profile along x over x_range (for plots and viewers)."""
        cuts = sorted({*x_range, *(c for g in self.gaps for c in (g.x0, g.x1)),
                       *(c for b in self.boxes for c in (b.x0, b.x1))})
        cuts = [c for c in cuts if x_range[0] <= c <= x_range[1]]
        mids = np.array([[(a + b) / 2, 0.0] for a, b in zip(cuts[:-1], cuts[1:])])
        return [(a, b, float(h)) for (a, b), h in zip(zip(cuts[:-1], cuts[1:]), self.height(mids))]
