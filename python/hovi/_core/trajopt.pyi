"""
Transcriptions of trajectory-optimisation problems
"""
from __future__ import annotations
import collections.abc
import hovi._core
import numpy
import numpy.typing
import typing
__all__: list[str] = ['BodyPointRows', 'ComplementarityRows', 'HermiteSimpsonTranscription', 'Program', 'RowBlock', 'VariationalTranscription', 'distance2_colouring', 'gram_pattern', 'star_colouring']
class VariationalTranscription:
    """
    The Galerkin VI of order 2s as NLP constraints (variational_transcription.hpp): variables q at the
    N s + 1 control points, p at the N + 1 knots, controls (per point or held per stage), multipliers
    λ^{k,0..s-1}; rows: per stage the s DEL residuals and the momentum update, then h(q^j).
    """
    def __init__(self, model: hovi._core.Model, s: typing.SupportsInt | typing.SupportsIndex, N: typing.SupportsInt | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex, controls: str = 'per_point') -> None:
        """
        N stages of the order-2s VI with step dt on a copy of `model`; controls 'per_point' or 'held'.
        """
    def constraints(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); returns g(x), (n_constraints,), the dynamics (and holonomic) constraints of the whole trajectory.
        """
    def jacobian(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); returns the Jacobian's values (nnz,) at x, in `structure` order.
        """
    @property
    def n_constraints(self) -> int:
        """
        Length of g(x).
        """
    @property
    def n_control_values(self) -> int:
        """
        Number of control samples (per point or per stage).
        """
    @property
    def n_points(self) -> int:
        """
        Number of control points N s + 1.
        """
    @property
    def n_variables(self) -> int:
        """
        Length of the variable vector x.
        """
    @property
    def nnz(self) -> int:
        """
        Number of nonzeros of the Jacobian.
        """
    @property
    def offsets(self) -> dict[str, int]:
        """
        Offsets of the variable blocks in x and of the first holonomic row.
        """
    @property
    def structure(self) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]]:
        """
        (rows (nnz,), cols (nnz,)) of the Jacobian's nonzeros, in the order `jacobian` returns values.
        """
class HermiteSimpsonTranscription:
    """
    Hermite-Simpson collocation as NLP constraints (hermite_simpson_transcription.hpp), implicit (a as
    variables, inverse-dynamics rows) or explicit (a = forward dynamics inside the collocation rows):
    variables q, v (and a) at the 2N + 1 knots and midpoints, controls, multipliers at every point.
    """
    def __init__(self, model: hovi._core.Model, N: typing.SupportsInt | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex, controls: str = 'per_point', implicit: bool = True) -> None:
        """
        N Hermite-Simpson intervals of length dt on a copy of `model`; controls 'per_point' or 'held'.
        """
    def constraints(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); returns g(x), (n_constraints,), the dynamics (and holonomic) constraints of the whole trajectory.
        """
    def jacobian(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); returns the Jacobian's values (nnz,) at x, in `structure` order.
        """
    @property
    def n_constraints(self) -> int:
        """
        Length of g(x).
        """
    @property
    def n_control_values(self) -> int:
        """
        Number of control samples (per point or per interval).
        """
    @property
    def n_points(self) -> int:
        """
        Number of points 2N + 1 (knots and midpoints).
        """
    @property
    def n_variables(self) -> int:
        """
        Length of the variable vector x.
        """
    @property
    def nnz(self) -> int:
        """
        Number of nonzeros of the Jacobian.
        """
    @property
    def offsets(self) -> dict[str, int]:
        """
        Offsets of the variable blocks in x.
        """
    @property
    def structure(self) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]]:
        """
        (rows (nnz,), cols (nnz,)) of the Jacobian's nonzeros, in the order `jacobian` returns values.
        """
class RowBlock:
    """
    Constraint rows beside the transcription that C++ evaluates with their own exact Hessian
    (row_block.hpp); a Program places them.
    """
    def hessian(self, x: numpy.typing.ArrayLike, lam: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x (n_variables,), lam (rows,): the Hessian of lam . rows at hessian_structure.
        """
    def jacobian(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x (n_variables,): the Jacobian's values (nnz,) in the order the NLP lists its structure.
        """
    def values(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x (n_variables,): the rows' values (rows,).
        """
    @property
    def hessian_structure(self) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]]:
        """
        (rows, cols) of the Hessian's lower-triangle entries (an entry may repeat; the values add).
        """
    @property
    def nnz(self) -> int:
        """
        Number of Jacobian values.
        """
    @property
    def rows(self) -> int:
        """
        Number of rows.
        """
class BodyPointRows(RowBlock):
    """
    Path constraints on body points sharing a set of configurations, each a weighted sum of the
    transcription's configuration points (body_point_rows.hpp): row (p, i) = c_i + sum_m L[i, m] . x_b
    + D[i, m] . x_b^2 with b = idx[i, m], x_b the world position of body point b at configuration p.
    """
    def __init__(self, model: hovi._core.Model, n_variables: typing.SupportsInt | typing.SupportsIndex, offsets: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"], weights: numpy.typing.ArrayLike, bodies: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], local: numpy.typing.ArrayLike, c: numpy.typing.ArrayLike, L: numpy.typing.ArrayLike, D: numpy.typing.ArrayLike, idx: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]) -> None:
        """
        offsets (P, K): where q of configuration p's k-th point starts in x; weights (P, K); bodies (B,), local (B, 3): the points; c (R,), L and D (R M, 3), idx (R, M): the rows' form (path_constraints.OnBodyPoints).
        """
class ComplementarityRows(RowBlock):
    """
    The contact complementarity rows of hovi.trajopt.ContactRows (complementarity_rows.hpp), values,
    Jacobian in its structure's order and exact Hessian.
    """
    def __init__(self, model: hovi._core.Model, n_variables: typing.SupportsInt | typing.SupportsIndex, contacts: hovi._core.ContactModel, first_input: typing.SupportsInt | typing.SupportsIndex, t: numpy.typing.ArrayLike, q_off: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], u_off: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"]) -> None:
        """
        The contacts (hovi.contact.Contacts.core_model()) on `model` (Contacts.with_inputs); first_input: the control index of the first contact input; t, q_off, u_off (P,): the configuration points' times and offsets of q and u in x.
        """
class Program:
    """
    The NLP of a transcribed problem evaluated in C++ (nlp_program.hpp), as hovi.trajopt.NLP lays it
    out: the quadratic costs c + sum_i d_i (S x - r)_i^2 / 2, rows [transcription | extra | A x], the Jacobian
    in `jac_rows`, `jac_cols` order, and the Lagrangian's Hessian by coloured differences once
    `set_colouring` gave the colours. The built-in rows (path constraints on body points, contact rows)
    are RowBlocks; the terms written in Python come through functions of x (each None when absent):
    extra_cost(x) -> (value, gradient), extra_constraints(x) -> (len(extra_rows),), extra_jacobian(x) ->
    (len(extra_entries),), one call per evaluation.
    """
    def __init__(self, transcription: VariationalTranscription | HermiteSimpsonTranscription, c: typing.SupportsFloat | typing.SupportsIndex, S: tuple[numpy.typing.ArrayLike, numpy.typing.ArrayLike, numpy.typing.ArrayLike], r: numpy.typing.ArrayLike, d: numpy.typing.ArrayLike, A: tuple[numpy.typing.ArrayLike, numpy.typing.ArrayLike, numpy.typing.ArrayLike], jac_rows: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], jac_cols: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], blocks: list = [], extra_cost: collections.abc.Callable[[numpy.typing.NDArray[numpy.float64]], typing.Any] | None = None, extra_constraints: collections.abc.Callable[[numpy.typing.NDArray[numpy.float64]], typing.Any] | None = None, extra_jacobian: collections.abc.Callable[[numpy.typing.NDArray[numpy.float64]], typing.Any] | None = None, extra_rows: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"] = ..., extra_entries: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"] = ...) -> None:
        """
        transcription: the C++ transcription; c, S (k, n), r (k,), d (k,): the quadratic costs; A (a, n): the linear rows (S, A as (indptr, indices, data) in compressed rows); jac_rows, jac_cols (nnz,): the whole Jacobian's structure; blocks: (RowBlock, rows, entries) tuples, the built-in rows with the places of their rows in g and of their Jacobian values; the extra terms (see the class), their rows at extra_rows and Jacobian values at extra_entries. Between the transcription's rows and A's every place is taken once.
        """
    def constraints(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); g(x) (n_constraints,).
        """
    def gradient(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); the cost's gradient (n_variables,).
        """
    def hessian(self, x: numpy.typing.ArrayLike, lam: numpy.typing.ArrayLike, sigma: typing.SupportsFloat | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x (n_variables,), lam (n_constraints,), sigma: the lower triangle of the Lagrangian's Hessian (E,) at the colouring's entries.
        """
    def jacobian(self, x: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        x: (n_variables,); the Jacobian's values (nnz,) in (jac_rows, jac_cols) order.
        """
    def objective(self, x: numpy.typing.ArrayLike) -> float:
        """
        x: (n_variables,); the total cost.
        """
    def probed_pattern(self, indptr: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], indices: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], x: numpy.typing.ArrayLike, seed: typing.SupportsInt | typing.SupportsIndex = 0, own_structures: bool = False) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]]:
        """
        The entries (indptr, indices) of the symmetric coupling pattern (indptr (n_variables + 1,), indices) where the Lagrangian's Hessian is not identically zero, probed at a random point near x (n_variables,) (lagrangian_hessian.hpp), with the quadratic costs' entries and the diagonal; own_structures: the transcription's (if it has one) and the built-in rows' entries from their own Hessians' values at that point, only the rest probed.
        """
    def set_colouring(self, colour: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], rows: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], cols: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], read_row: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], read_col: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], threads: int | None = 1, by_differences: bool = False) -> None:
        """
        colour (n_variables,); the lower triangle's entries rows >= cols (E,) and where each is read: component read_row of the difference of read_col's colour (hovi.trajopt.hessian.LagrangianHessian); threads: for the transcription's Hessian or its colours' differences (None: HOVI_NUM_THREADS or every core; the extra terms on the calling thread); by_differences: difference the transcription's and the built-in rows' parts even where they have Hessians of their own (the VI's, del_hessian.hpp; the RowBlocks').
        """
    def set_hessian_options(self, threads: int | None, by_differences: bool) -> None:
        """
        The Hessian's threads and whether it differences the parts that have Hessians of their own (as set_colouring), its colours kept.
        """
    @property
    def has_hessian(self) -> bool:
        """
        Whether set_colouring gave the Hessian its colours.
        """
    @property
    def hessian_threads(self) -> int:
        """
        Threads of the Hessian (0 without a Hessian).
        """
    @property
    def n_constraints(self) -> int:
        """
        Length of g(x).
        """
    @property
    def n_variables(self) -> int:
        """
        Length of x.
        """
    @property
    def nnz(self) -> int:
        """
        Jacobian nonzeros.
        """
    @property
    def transcription_hessian(self) -> bool:
        """
        Whether the Hessian takes the transcription's part from its own Hessian (not differenced).
        """
def distance2_colouring(indptr: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], indices: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"]) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
    """
    Distance-2 colours (nv,) of the symmetric pattern in compressed rows (indptr (nv + 1,), indices) (colouring.hpp).
    """
def gram_pattern(indptr: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], indices: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], n: typing.SupportsInt | typing.SupportsIndex) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]]:
    """
    The symmetric pattern (indptr (n+1,), indices) of A^T A + I for the pattern A in compressed rows (indptr, indices < n) (colouring.hpp).
    """
def star_colouring(indptr: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], indices: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"]) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
    """
    Star colours (nv,) of the symmetric pattern in compressed rows (indptr (nv + 1,), indices) (colouring.hpp).
    """
