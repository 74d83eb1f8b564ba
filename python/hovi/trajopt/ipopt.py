"""Deprecated module (one release): IPOPT moved to ``hovi.trajopt.solvers.ipopt`` (``Ipopt``,
``solve``), the transcription choice to ``hovi.trajopt.VI`` / ``HermiteSimpson``, the initial guess
to ``Transcription.initial_guess``."""
from __future__ import annotations

import warnings

from . import transcription as transcription_module
from . import transcriptions as transcriptions_module
from .solvers import ipopt as ipopt_module


def initial_guess(tr, guess):
    """Deprecated: ``tr.initial_guess(guess)``."""
    warnings.warn("hovi.trajopt.ipopt.initial_guess(tr, guess) is deprecated: use tr.initial_guess(guess)",
                  DeprecationWarning, stacklevel=2)
    return tr.initial_guess(guess)


MOVED = {"solve": (ipopt_module, "hovi.trajopt.solve"),
         "DEFAULT_OPTIONS": (ipopt_module, "hovi.trajopt.solvers.ipopt.DEFAULT_OPTIONS"),
         "transcribe": (transcriptions_module, "hovi.trajopt.VI(s).transcribe(problem)"),
         "Guess": (transcription_module, "hovi.trajopt.Guess")}


def __getattr__(name: str):
    if name in MOVED:
        module, new = MOVED[name]
        warnings.warn(f"hovi.trajopt.ipopt.{name} is deprecated: use {new}", DeprecationWarning, stacklevel=2)
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
