"""
Transcriptions of trajectory-optimisation problems
"""
from __future__ import annotations
import hovi._core
import numpy
import numpy.typing
import typing
__all__: list[str] = ['HermiteSimpsonTranscription', 'VariationalTranscription']
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
