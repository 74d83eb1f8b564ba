"""Deprecated: moved to ``hovi.examples.robots`` (this alias goes in the next release)."""
import warnings

from .examples.robots import *  # noqa: F401,F403
from .examples.robots import __all__  # noqa: F401

warnings.warn("hovi.robots is deprecated: use hovi.examples.robots", DeprecationWarning, stacklevel=2)
