"""Samples of a transcribed trajectory: where costs are evaluated.

A transcription exposes its trajectory to costs only through samples: per stage, the points of
its quadrature rule (the VI's Lobatto control points; Hermite-Simpson's knot, midpoint, knot),
with times ``t``, quadrature weights ``w`` (so that sum_j w_j L(t_j, ...) approximates the
integral of L over the horizon) and the configuration, velocity and control at each, all linear
in the NLP variables x: ``q = Sq x``, ``v = Sv x``, ``u = Su x`` (sparse matrices). A cost term
sees the arrays and returns its gradient with respect to them; the chain rule through the
sparse maps is the NLP's job. So a cost does not know the transcription.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass
class SampleMap:
    t: np.ndarray        # (K,) sample times
    w: np.ndarray        # (K,) quadrature weights
    Sq: sp.csr_matrix    # (K n, n_variables)
    Sv: sp.csr_matrix    # (K n, n_variables)
    Su: sp.csr_matrix    # (K m, n_variables)
    n: int
    m: int
    final: int           # index of the sample at the final time

    def evaluate(self, x: np.ndarray) -> "Samples":
        K = len(self.t)
        return Samples(self.t, self.w, (self.Sq @ x).reshape(K, self.n), (self.Sv @ x).reshape(K, self.n),
                       (self.Su @ x).reshape(K, self.m), self.final)

    def pullback(self, dq: np.ndarray, dv: np.ndarray, du: np.ndarray) -> np.ndarray:
        """The gradient with respect to x of a function whose gradients with respect to the
        samples' q, v, u are dq, dv, du."""
        return self.Sq.T @ dq.ravel() + self.Sv.T @ dv.ravel() + self.Su.T @ du.ravel()


@dataclass
class Samples:
    t: np.ndarray   # (K,)
    w: np.ndarray   # (K,)
    q: np.ndarray   # (K, n)
    v: np.ndarray   # (K, n)
    u: np.ndarray   # (K, m)
    final: int      # the sample at the final time
