"""Resolving a body given by name or index against a model, with a message naming what is wrong."""
from __future__ import annotations

from ._core import Model


def body_index(model: Model, body: int | str, what: str = "body") -> int:
    """The index of ``body`` (a name or an index) in ``model``; ValueError naming the unknown ``what``."""
    if isinstance(body, str):
        if body not in model.body_names:
            raise ValueError(f"unknown {what} '{body}' (the model's bodies: {', '.join(model.body_names)})")
        return model.body_index(body)
    b = int(body)
    if not 0 <= b < model.n:
        raise ValueError(f"unknown {what} {b}: index out of range (the model has {model.n} bodies)")
    return b
