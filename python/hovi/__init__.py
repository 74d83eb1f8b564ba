"""hovi: higher-order variational integrators for robots.

An Eigen C++ core with pybind11 bindings implementing Fan, Schultz and Murphey, "Efficient
Computation of Higher-Order Variational Integrators in Robotic Simulation and Trajectory
Optimization" (WAFR 2018).
"""
from ._core import Model, ModelError, URDFError
from . import examples
from .batch import JacobianBatch, StepBatch, TrajectoryBatch
from .integrator import ConvergenceError, Integrator
from .linearizer import DelJacobian, Linearizer, StepLinearization
from .pinocchio_bridge import from_pinocchio
from .trajectory import Discretization, StepInfo, Trajectory, load_trajectory

__all__ = ["Model", "ModelError", "URDFError", "examples", "Integrator", "ConvergenceError", "StepInfo",
           "Trajectory", "TrajectoryBatch", "StepBatch", "Linearizer", "DelJacobian", "StepLinearization",
           "JacobianBatch", "load_trajectory", "Discretization", "from_pinocchio"]
__version__ = "0.1.0"  # the one place the version is kept: pyproject.toml reads it from here
