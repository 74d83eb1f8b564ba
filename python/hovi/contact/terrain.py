"""Terrain for contact: a ground plane at height ``ground`` with gaps (strips where the ground is
missing) and boxes (raised blocks), all with horizontal top faces, so the surface normal is +z
wherever a foot can stand. The signed gap of a world point is its height above the surface below
it, phi(x) = z - h(x, y), with h piecewise constant (its gradient is (0, 0, 1) away from edges)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Sequence, Tuple

import numpy as np


@dataclass
class Gap:
    """No ground for x0 < x < x1 (a strip across y), down to ``depth`` below the ground."""
    x0: float
    x1: float
    depth: float = 1.0


@dataclass
class Box:
    """A block with its top face at height ``top`` over x0 < x < x1, y0 < y < y1."""
    x0: float
    x1: float
    top: float
    y0: float = -np.inf
    y1: float = np.inf


@dataclass
class Terrain:
    """Flat ground at height ``ground`` with ``gaps`` and ``boxes`` (boxes stand above gaps)."""
    ground: float = 0.0
    gaps: List[Gap] = field(default_factory=list)
    boxes: List[Box] = field(default_factory=list)

    def __post_init__(self) -> None:
        for g in self.gaps:
            if not (np.isfinite(g.x0) and np.isfinite(g.x1) and g.x0 < g.x1 and g.depth > 0):
                raise ValueError(f"a gap needs finite x0 < x1 and a positive depth, got {g}")
        for b in self.boxes:
            if not (b.x0 < b.x1 and b.y0 < b.y1 and np.isfinite(b.top)):
                raise ValueError(f"a box needs x0 < x1, y0 < y1 and a finite top, got {b}")

    def height(self, xy: np.ndarray) -> np.ndarray:
        """h (P,) of the surface below the points xy (P, 2)."""
        xy = np.atleast_2d(xy)
        h = np.full(len(xy), float(self.ground))
        for g in self.gaps:
            h[(xy[:, 0] > g.x0) & (xy[:, 0] < g.x1)] = self.ground - g.depth
        for b in self.boxes:
            inside = (xy[:, 0] > b.x0) & (xy[:, 0] < b.x1) & (xy[:, 1] > b.y0) & (xy[:, 1] < b.y1)
            h[inside] = np.maximum(h[inside], b.top)
        return h

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
