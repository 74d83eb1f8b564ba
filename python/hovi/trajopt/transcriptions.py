"""The transcriptions to choose from (``VI``, ``HermiteSimpson``), the one every entry point uses by
default (``DEFAULT_TRANSCRIPTION``), and the strings the command line spells them with
(``from_name``: 'vi' with an order, 'hs-implicit', 'hs-explicit')."""
from __future__ import annotations

from .hermite_simpson import HermiteSimpson
from .transcription import TranscriptionMethod
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


def transcription_method(transcription: object) -> TranscriptionMethod:
    """``transcription`` itself, if it is a ``VI`` or ``HermiteSimpson``; else ValueError (a string) or
    TypeError naming what to give."""
    if isinstance(transcription, str):
        raise ValueError(f"transcription must be a hovi.trajopt.VI or HermiteSimpson, not a string ({transcription!r}): "
                         "e.g. hovi.trajopt.VI(s=2) or hovi.trajopt.HermiteSimpson('implicit')")
    if not isinstance(transcription, TranscriptionMethod):
        raise TypeError(f"transcription must be a hovi.trajopt.VI or HermiteSimpson (e.g. hovi.trajopt.VI(s=2)), "
                        f"got {transcription!r:.60}")
    return transcription
