"""Deprecated: moved to ``hovi.examples.swingups`` (this alias goes in the next release)."""
import warnings

from ..examples.swingups import *  # noqa: F401,F403
from ..examples.swingups import EXAMPLES, __all__  # noqa: F401

warnings.warn("hovi.trajopt.examples is deprecated: use hovi.examples.swingups (or hovi.examples.entries('optimization'))",
              DeprecationWarning, stacklevel=2)
