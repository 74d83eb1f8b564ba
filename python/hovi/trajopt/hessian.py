"""The Hessian of the NLP's Lagrangian, sigma f(x) + lambda^T g(x), for IPOPT's Newton steps
(``solve(..., hessian='fd')``; with the default, 'directional', the VI's DEL equations take their
own Hessian, del_hessian.hpp, the built-in path constraints and contact rows theirs, and only the
Python terms' part is differenced this way, over the same pattern and colours): forward differences of its analytic gradient sigma grad f + J^T lambda
(the exact sparse Jacobian of the transcription) along coloured directions: variables of one colour
move together, one difference each, so a Hessian costs one gradient and Jacobian evaluation per
colour, not per variable. The colours are a star colouring of the Hessian's pattern (Powell and
Toint's symmetric method, in the graph form of Gebremedhin, Manne and Pothen, "What color is your
Jacobian?", SIAM Review 2005): every entry H_ij is read from the difference of j's colour in row i
or, by symmetry, from that of i's colour in row j, whichever has no other variable of its colour
coupled to the row. Curtis, Powell and Reid's distance-2 colouring (no symmetry) needs at least
as many colours as the densest row has entries; a star colouring lets a dense row (a variable
coupled to a whole stage) be read from its own column, and needs far fewer colours.

Why: with IPOPT's limited-memory approximation the large robot examples (Atlas) do not converge;
with this Hessian they do. The colour counts and iterations are in bench/README.md ("Design
measurements", trajopt/hessian.py).

Assumes the costs couple variables only within one sample (ControlEffort, StateTracking,
TerminalCost); a CallbackCost may couple anything, so it is refused.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .. import _core

from .costs import CallbackCost
from .nlp import NLP


def _pattern(M: sp.spmatrix) -> sp.csr_matrix:
    M = sp.csr_matrix(M, copy=True)
    M.data[:] = 1.0
    return M


def _compressed(P: sp.spmatrix) -> tuple[np.ndarray, np.ndarray]:
    P = sp.csr_matrix(P)
    return P.indptr.astype(np.int32), P.indices.astype(np.int32)


def star_colouring(P: sp.csr_matrix) -> np.ndarray:
    """Greedy star colours (nv,) of the symmetric pattern P (nv, nv; its diagonal is ignored), the
    densest rows first (GMP 2005, Algorithm 4.1; in C++, colouring.hpp): coupled variables differ,
    and on every path v-w-x-y the colours of v, x and of w, y are not both equal, so that each
    coupled pair (i, j) has one side, say i, with no other variable of j's colour coupled to it."""
    return _core.trajopt.star_colouring(*_compressed(P)).astype(np.int64)


def distance2_colouring(P: sp.csr_matrix) -> np.ndarray:
    """Greedy colours (nv,) of the symmetric pattern P (nv, nv) with the diagonal: no two variables
    with a common neighbour share a colour (in C++, colouring.hpp)."""
    return _core.trajopt.distance2_colouring(*_compressed(P)).astype(np.int64)


# Colourings by Hessian pattern (after probing), the most recently used last: a second solve of a
# problem of the same structure (a warm start, a sweep, MPC) colours nothing.
_COLOURINGS: dict[tuple, tuple[np.ndarray, ...]] = {}
_CACHED_COLOURINGS = 32


class LagrangianHessian:
    """The pattern of the lower triangle of the Lagrangian's Hessian of ``nlp``, ``structure`` (rows,
    cols), and its star colouring (``colour``; entry e is read as component ``read_row[e]`` of the
    difference of ``read_col[e]``'s colour), which the C++ program differences
    (``Program.set_colouring``: the one evaluation of the coloured Hessian).

    The coupling graph over-estimates the Hessian: a constraint row involving x_j and x_k need not
    have a second derivative in them (the inputs enter the dynamics and the contact rows linearly,
    and the momenta the dynamics). Given ``probe``, a point (n_variables,) where the NLP's functions
    can be evaluated, the pattern is narrowed to the entries found there (``probed_pattern``) and
    coloured again: fewer colours and nonzeros (bench/README.md, "Design measurements").
    ``solve(hessian='fd')`` probes near its starting point. ``own_structures``: the parts with
    Hessians of their own (the VI's, the built-in rows') give the entries of those Hessians that
    are above 1e-14 of their largest at the probe point, and only the rest is probed
    ('directional' and 'auto': nothing is probed without Hermite-Simpson or terms written in Python)."""

    def __init__(self, nlp: NLP, probe: np.ndarray | None = None, seed: int = 0, own_structures: bool = False):
        if any(isinstance(c, CallbackCost) for c in nlp.problem.costs):
            raise ValueError("hessian='fd' needs costs that couple variables only within a sample; a CallbackCost "
                             "may couple any of them (use hessian='lbfgs')")
        self.nlp = nlp
        nv, nc = nlp.n_variables, nlp.n_constraints
        # variables coupled by a constraint row or by a sample (the costs couple only within one)
        s = nlp.samples
        K = len(s.t)
        per_sample = [(S.tocoo(), S.shape[0] // K) for S in (s.Sq, s.Sv, s.Su) if S.shape[0]]
        rows = np.concatenate([nlp.jac_rows] + [nc + S.row // width for S, width in per_sample])
        cols = np.concatenate([nlp.jac_cols] + [S.col for S, _ in per_sample])
        A = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), (nc + K, nv))
        indptr, indices = _core.trajopt.gram_pattern(*_compressed(A), nv)
        P = sp.csr_matrix((np.ones(len(indices)), indices, indptr), (nv, nv))
        if probe is not None:
            P = self._probed_once(P, np.asarray(probe, float), seed, own_structures)
        P.sort_indices()
        key = (nv, P.indptr.tobytes(), P.indices.tobytes())
        cached = _COLOURINGS.pop(key, None)
        if cached is None:
            cached = self._colouring(P)
        _COLOURINGS[key] = cached                       # the most recent last
        while len(_COLOURINGS) > _CACHED_COLOURINGS:
            del _COLOURINGS[next(iter(_COLOURINGS))]
        self.colour, self.rows, self.cols, self.read_row, self.read_col = cached
        self.n_colours = int(self.colour.max()) + 1 if nv else 0

    @staticmethod
    def _colouring(P: sp.csr_matrix) -> tuple[np.ndarray, ...]:
        """(colour, rows, cols, read_row, read_col) of the Hessian's pattern P."""
        nv = P.shape[0]
        colour = star_colouring(P)
        P = P.tocoo()
        lower = P.row >= P.col
        rows, cols = P.row[lower].astype(np.int64), P.col[lower].astype(np.int64)
        # where each entry is read: row i of the difference of j's colour, unless another variable
        # of that colour is coupled to i; then row j of the difference of i's colour (star colouring)
        count = np.zeros((nv, int(colour.max()) + 1 if nv else 0), np.int32)
        np.add.at(count, (P.row, colour[P.col]), 1)
        alone = count[rows, colour[cols]] == 1
        # entry e is component read_row[e] of the difference of read_col[e]'s colour
        return colour, rows, cols, np.where(alone, rows, cols), np.where(alone, cols, rows)

    def _probed_once(self, P: sp.csr_matrix, x: np.ndarray, seed: int, own_structures: bool) -> sp.csr_matrix:
        """``probed_pattern``, kept on the transcription by coupling pattern and terms: the NLPs over
        it that differ only in bounds (a contact homotopy's relaxed and exact solves) probe once."""
        nlp = self.nlp
        terms = (*nlp.problem.costs, *(c for c, *_ in nlp.paths), nlp.problem.contacts)
        key = (P.indptr.tobytes(), P.indices.tobytes(), seed, own_structures, tuple(map(id, terms)))
        cache = nlp.transcription.probed_patterns
        if key not in cache:   # the terms kept with it: their ids cannot pass to other objects
            cache[key] = (self.probed_pattern(P, x, seed, own_structures), terms)
        return cache[key][0]

    def probed_pattern(self, P: sp.csr_matrix, x: np.ndarray, seed: int = 0, own_structures: bool = False) -> sp.csr_matrix:
        """The entries of the coupling pattern P (symmetric, with the diagonal) where the Hessian is
        not identically zero, found at a random point near x with random multipliers (in C++,
        ``Program.probed_pattern``): for each distance-2 colour of P, the gradient's change when that
        colour's variables move by about 10% (not a derivative: any dependence shows) names, in each
        changed component i, the one variable of that colour coupled to i; the quadratic costs'
        entries and the diagonal are added. Assumes that where a function depends on a variable
        somewhere, it does near x (no piece of a piecewise function on which the dependence
        vanishes). An entry missed there leaves IPOPT's Newton steps inexact, not its answer: IPOPT's
        convergence tests use the exact gradient and Jacobian, so a wrong Hessian costs iterations,
        never feasibility. ``own_structures`` as in the constructor."""
        indptr, indices = _compressed(P)
        indptr, indices = self.nlp.program().probed_pattern(indptr, indices, np.asarray(x, float), seed, own_structures)
        nv = self.nlp.n_variables
        return sp.csr_matrix((np.ones(len(indices)), indices, indptr), (nv, nv))

    @property
    def structure(self) -> tuple[np.ndarray, np.ndarray]:
        """(rows, cols) of the lower triangle's nonzeros."""
        return self.rows, self.cols
