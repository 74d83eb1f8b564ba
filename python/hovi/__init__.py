"""hovi: higher-order variational integrators for robots.

An Eigen C++ core with pybind11 bindings implementing Fan, Schultz and Murphey, "Efficient
Computation of Higher-Order Variational Integrators in Robotic Simulation and Trajectory
Optimization" (WAFR 2018).
"""
import warnings as _warnings
from typing import Any as _Any

from ._core import Model, ModelError, URDFError
from . import examples
from .batch import JacobianBatch, StepBatch, TrajectoryBatch
from .integrator import ConvergenceError, Integrator
from .linearizer import DelJacobian, Linearizer, StepLinearization
from .trajectory import Discretization, StepInfo, Trajectory, load_trajectory

__all__ = ["Model", "ModelError", "URDFError", "examples", "Integrator", "ConvergenceError", "StepInfo",
           "Trajectory", "TrajectoryBatch", "StepBatch", "Linearizer", "DelJacobian", "StepLinearization",
           "JacobianBatch", "load_trajectory", "Discretization"]
__version__ = "0.1.0"  # the one place the version is kept: pyproject.toml reads it from here


def __getattr__(name: str) -> _Any:
    """The deprecated ``hovi.models`` and ``hovi.robots`` (now hovi.examples.models, hovi.examples.robots)."""
    if name in ("models", "robots"):
        _warnings.warn(f"hovi.{name} is deprecated: use hovi.examples.{name}", DeprecationWarning, stacklevel=2)
        from importlib import import_module
        return import_module(f"{__name__}.examples.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
