"""The transcriptions to choose from (``VI``, ``HermiteSimpson``), the one every entry point uses by
default (``DEFAULT_TRANSCRIPTION``), and the strings the command line spells them with
(``from_name``: 'vi' with an order, 'hs-implicit', 'hs-explicit')."""
from __future__ import annotations

import warnings

from .hermite_simpson import HermiteSimpson
from .problem import Problem
from .transcription import Transcription, TranscriptionMethod
from .variational import VI

DEFAULT_TRANSCRIPTION = VI(s=2)

NAMES = ("vi", "hs-implicit", "hs-explicit")


def from_name(name: str, s: int = 2) -> TranscriptionMethod:
    """The transcription spelled ``name``: 'vi' (the Galerkin VI of order 2s), 'hs' or 'hs-implicit'
    (implicit Hermite-Simpson) or 'hs-explicit' (``s`` is the VI's only)."""
    if name == "vi":
        return VI(s)
    if name in ("hs", "hs-implicit"):
        return HermiteSimpson("implicit")
    if name == "hs-explicit":
        return HermiteSimpson("explicit")
    raise ValueError(f"transcription must be 'vi', 'hs-implicit' or 'hs-explicit', got '{name}'")


def resolve(transcription: TranscriptionMethod | str | None, s: int | None = None, *, old_default_s: int = 2,
            caller: str = "solve") -> TranscriptionMethod:
    """The TranscriptionMethod an entry point was given: ``transcription`` itself (None: the
    default); the old spellings (a string and ``s=``; ``s=`` alone meant the VI of that order, its
    default ``old_default_s``) still work for one release, with a DeprecationWarning."""
    if s is None and (transcription is None or isinstance(transcription, TranscriptionMethod)):
        return DEFAULT_TRANSCRIPTION if transcription is None else transcription
    if transcription is not None and not isinstance(transcription, (str, TranscriptionMethod)):
        raise TypeError(f"transcription must be a hovi.trajopt.VI or HermiteSimpson, got {type(transcription).__name__}")
    old = "vi" if transcription is None or (transcription is DEFAULT_TRANSCRIPTION and s is not None) else transcription
    new = from_name(old, old_default_s if s is None else s) if isinstance(old, str) else old
    if isinstance(old, TranscriptionMethod) and s is not None:
        raise TypeError(f"s= goes with the old string spellings only; give the order in the transcription: {old!r}")
    warnings.warn(f"{caller}(problem, {old!r}{'' if s is None else f', s={s}'}) is deprecated: use "
                  f"{caller}(problem, hovi.trajopt.{new!r})", DeprecationWarning, stacklevel=3)
    return new


def transcribe(problem: Problem, transcription: str = "vi", s: int = 2) -> Transcription:
    """Deprecated: ``hovi.trajopt.VI(s).transcribe(problem)`` (or ``HermiteSimpson(form)``)."""
    method = from_name(transcription, s)
    warnings.warn(f"transcribe(problem, {transcription!r}, {s}) is deprecated: use "
                  f"hovi.trajopt.{method!r}.transcribe(problem)", DeprecationWarning, stacklevel=2)
    return method.transcribe(problem)
