"""Deprecated: the trajectory file format moved to ``hovi.trajectory`` (``hovi.load_trajectory`` and
``Trajectory.save`` are unchanged)."""
import warnings

from .trajectory import FORMAT_VERSION, load_trajectory, save_trajectory

warnings.warn("hovi.trajectory_io is deprecated: use hovi.trajectory (or hovi.load_trajectory)", DeprecationWarning,
              stacklevel=2)

__all__ = ["FORMAT_VERSION", "load_trajectory", "save_trajectory"]
