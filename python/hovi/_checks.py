"""Checks of user input shared by the Python layers (trajectory files, trajopt, contact): each
refusal is a ValueError whose message names the argument and says what is wrong with it (as the
core's own checks: a complex or text array is a ValueError there too). Nothing is cast silently:
complex, object, string and boolean arrays are refused where real numbers are expected."""
from __future__ import annotations

import numbers
from typing import Any, Optional, Sequence

import numpy as np

from . import _core


def real_array(value: Any, name: str, shape: Optional[Sequence[Optional[int]]] = None, *,
               finite: bool = True) -> np.ndarray:
    """``value`` as a new float64 array. ValueError for something that is not an array of real
    numbers (strings, objects, complex, booleans, None: ``_core.real_array``, the core's one test),
    a shape other than ``shape`` (None entries match any length) or, with ``finite``, NaN or
    infinity; every message names ``name``."""
    a = np.array(_core.real_array(value, name), dtype=np.float64)  # a copy: the caller's array is never shared
    if shape is not None and (a.ndim != len(shape)
                              or any(w is not None and w != g for w, g in zip(shape, a.shape))):
        wanted = "(" + ", ".join("any" if w is None else str(w) for w in shape) + ("," if len(shape) == 1 else "") + ")"
        raise ValueError(f"{name} must have shape {wanted}, got shape {a.shape}")
    if finite and not np.all(np.isfinite(a)):
        bad = np.argwhere(~np.isfinite(a))[0]
        where = f" at index {tuple(int(i) for i in bad)}" if a.ndim else ""
        raise ValueError(f"{name} must be finite, got {a[tuple(bad)] if a.ndim else a}{where}")
    return a


def real_number(value: Any, name: str, *, finite: bool = True, minimum: Optional[float] = None,
                maximum: Optional[float] = None, strict_minimum: bool = False) -> float:
    """``value`` as a float: a real number (not a bool, string or complex), finite with ``finite``,
    >= ``minimum`` (> with ``strict_minimum``) and <= ``maximum``; ValueError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
            value = value.item()
        else:
            raise ValueError(f"{name} must be a real number, got {type(value).__name__} {value!r:.60}")
    try:
        x = float(value)
    except OverflowError:
        raise ValueError(f"{name} must be a finite number, got {value!r:.40}") from None
    if np.isnan(x) and not finite:
        raise ValueError(f"{name} must be a number (+-inf allowed), got nan")
    if finite and not np.isfinite(x):
        raise ValueError(f"{name} must be a finite number, got {x}")
    if minimum is not None and (x <= minimum if strict_minimum else x < minimum):
        raise ValueError(f"{name} must be {'>' if strict_minimum else '>='} {minimum:g}, got {x:g}")
    if maximum is not None and x > maximum:
        raise ValueError(f"{name} must be <= {maximum:g}, got {x:g}")
    return x


def step_count(steps: Any, name: str = "steps") -> int:
    """A number of steps as an int: ValueError naming ``name`` for a float (even 10.0: ``int()`` would
    truncate 10.5 silently), a string, a bool or a negative number. The one check of every step count."""
    if isinstance(steps, (bool, np.bool_)) or not isinstance(steps, (int, np.integer)):
        raise ValueError(f"{name} must be a whole number (an int), got {steps!r} ({type(steps).__name__})")
    if steps < 0:
        raise ValueError(f"{name} must be non-negative")
    return int(steps)


def whole_number(value: Any, name: str, *, minimum: int = 0) -> int:
    """``value`` as an int: an integer (a float only if it is whole; not a bool or string) >= ``minimum``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.integer, np.floating)):
        raise ValueError(f"{name} must be a whole number, got {type(value).__name__} {value!r:.60}")
    if isinstance(value, (numbers.Integral, np.integer)):
        value = int(value)
    elif not np.isfinite(float(value)) or int(value) != value:
        raise ValueError(f"{name} must be a whole number, got {value!r}")
    if int(value) < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {int(value)}")
    return int(value)
