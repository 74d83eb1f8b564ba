"""Deprecated: moved to ``hovi.examples.models`` (this alias goes in the next release)."""
import warnings

from .examples.models import *  # noqa: F401,F403
from .examples.models import __all__  # noqa: F401

warnings.warn("hovi.models is deprecated: use hovi.examples.models", DeprecationWarning, stacklevel=2)
